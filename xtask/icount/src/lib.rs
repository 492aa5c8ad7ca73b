//! `icount`: a QEMU TCG plugin (API version 1, QEMU 7.2) that counts the guest instructions a
//! firmware executes between calls of its marker functions.
//!
//! Arguments (`-plugin libicount.so,start=0x..,stop=0x..,frame=0x..[,profile=on]`): the
//! addresses of `microray_count_start`, `_stop` and `_frame`. Every instruction adds one to a
//! counter inline (and VDIV/VSQRT instructions to their own); the markers are matched by
//! address (never by symbol within a translation block, which would count a marker that
//! straddles a page twice) and read the counters: `start` takes a snapshot, `stop` adds what
//! was executed since, `frame` prints `icount frame N insns I vdiv D vsqrt Q` and starts a new
//! frame. With `profile=on`, every instruction address also has its own counter: `start` and
//! `stop` read them too, and `frame` prints `icount addr N ADDRESS COUNT` for each address
//! executed while counting (the instructions of the frame by address, which `cargo xtask qemu
//! --profile` maps to functions, inlined ones included, and to stages), then `icount frame`.
//!
//! The plugin API is C; this is the only `unsafe` code of the project, each call as QEMU's
//! `qemu-plugin.h` documents it.
#![allow(non_upper_case_globals)]

use std::collections::HashMap;
use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::sync::Mutex;

type PluginId = u64;

#[repr(C)]
struct Tb {
    _opaque: [u8; 0],
}

#[repr(C)]
struct Insn {
    _opaque: [u8; 0],
}

const INLINE_ADD_U64: c_int = 0;
const CB_NO_REGS: c_int = 0;

unsafe extern "C" {
    fn qemu_plugin_register_vcpu_tb_trans_cb(id: PluginId, cb: extern "C" fn(PluginId, *mut Tb));
    fn qemu_plugin_tb_n_insns(tb: *const Tb) -> usize;
    fn qemu_plugin_tb_get_insn(tb: *const Tb, index: usize) -> *mut Insn;
    fn qemu_plugin_insn_vaddr(insn: *const Insn) -> u64;
    fn qemu_plugin_insn_disas(insn: *const Insn) -> *mut c_char;
    fn qemu_plugin_register_vcpu_insn_exec_inline(
        insn: *mut Insn,
        op: c_int,
        ptr: *mut c_void,
        imm: u64,
    );
    fn qemu_plugin_register_vcpu_insn_exec_cb(
        insn: *mut Insn,
        cb: extern "C" fn(u32, *mut c_void),
        flags: c_int,
        userdata: *mut c_void,
    );
    fn qemu_plugin_outs(string: *const c_char);
    fn free(pointer: *mut c_void);
}

/// The plugin API version this plugin was written against (QEMU 7.2's).
#[unsafe(no_mangle)]
pub static qemu_plugin_version: c_int = 1;

/// Counters that QEMU's generated code adds to inline: one vCPU, so plain memory.
#[repr(C)]
struct Counters {
    insns: u64,
    vdiv: u64,
    vsqrt: u64,
}

static mut COUNTERS: Counters = Counters {
    insns: 0,
    vdiv: 0,
    vsqrt: 0,
};

struct State {
    start: u64,
    stop: u64,
    frame: u64,
    profile: bool,
    /// Counter values at the last `start`.
    since: [u64; 3],
    /// What the current frame has executed.
    frame_total: [u64; 3],
    frames: u64,
    /// Per-address counters (profile only, leaked: they live as long as QEMU): the
    /// address, its counter, and the counter's value when counting last started.
    addresses: Vec<(u64, &'static mut u64, u64)>,
    index: HashMap<u64, usize>,
    /// Per-address instructions counted in the frame so far.
    frame_addresses: HashMap<u64, u64>,
}

static STATE: Mutex<Option<State>> = Mutex::new(None);

fn snapshot() -> [u64; 3] {
    // SAFETY: one vCPU; QEMU's inline adds and this read happen on the same thread.
    unsafe {
        let c = &*std::ptr::addr_of!(COUNTERS);
        [c.insns, c.vdiv, c.vsqrt]
    }
}

fn output(text: &str) {
    if let Ok(line) = CString::new(text) {
        // SAFETY: a NUL-terminated string QEMU copies.
        unsafe { qemu_plugin_outs(line.as_ptr()) };
    }
}

const MARK_START: usize = 1;
const MARK_STOP: usize = 2;
const MARK_FRAME: usize = 3;

extern "C" fn on_marker(_vcpu: u32, userdata: *mut c_void) {
    let now = snapshot();
    let Ok(mut guard) = STATE.lock() else { return };
    let Some(state) = guard.as_mut() else { return };
    match userdata as usize {
        MARK_START => {
            state.since = now;
            for (_, counter, since) in &mut state.addresses {
                *since = **counter;
            }
        }
        MARK_STOP => {
            for ((total, now), since) in state.frame_total.iter_mut().zip(now).zip(state.since) {
                *total += now - since;
            }
            for (address, counter, since) in &mut state.addresses {
                let executed = **counter - *since;
                if executed != 0 {
                    *state.frame_addresses.entry(*address).or_insert(0) += executed;
                    *since = **counter;
                }
            }
        }
        MARK_FRAME => {
            let mut executed: Vec<(u64, u64)> = state.frame_addresses.drain().collect();
            executed.sort_unstable();
            let mut text = String::new();
            for (address, count) in executed {
                text.push_str(&format!(
                    "icount addr {} {address:#x} {count}\n",
                    state.frames
                ));
            }
            output(&text);
            let [insns, vdiv, vsqrt] = state.frame_total;
            output(&format!(
                "icount frame {} insns {insns} vdiv {vdiv} vsqrt {vsqrt}\n",
                state.frames
            ));
            state.frames += 1;
            state.frame_total = [0; 3];
        }
        _ => {}
    }
}

extern "C" fn on_translate(_id: PluginId, tb: *mut Tb) {
    let Ok(mut guard) = STATE.lock() else { return };
    let Some(state) = guard.as_mut() else { return };
    // SAFETY: `tb` and its instructions are valid during this callback, as the API says.
    unsafe {
        let counters = &raw mut COUNTERS;
        for index in 0..qemu_plugin_tb_n_insns(tb) {
            let insn = qemu_plugin_tb_get_insn(tb, index);
            qemu_plugin_register_vcpu_insn_exec_inline(
                insn,
                INLINE_ADD_U64,
                (&raw mut (*counters).insns).cast(),
                1,
            );
            let text = qemu_plugin_insn_disas(insn);
            if !text.is_null() {
                let mnemonic = CStr::from_ptr(text)
                    .to_string_lossy()
                    .trim_start()
                    .to_ascii_lowercase();
                if mnemonic.starts_with("vdiv") {
                    qemu_plugin_register_vcpu_insn_exec_inline(
                        insn,
                        INLINE_ADD_U64,
                        (&raw mut (*counters).vdiv).cast(),
                        1,
                    );
                } else if mnemonic.starts_with("vsqrt") {
                    qemu_plugin_register_vcpu_insn_exec_inline(
                        insn,
                        INLINE_ADD_U64,
                        (&raw mut (*counters).vsqrt).cast(),
                        1,
                    );
                }
                free(text.cast());
            }
            let address = qemu_plugin_insn_vaddr(insn);
            let mark = if address == state.start {
                MARK_START
            } else if address == state.stop {
                MARK_STOP
            } else if address == state.frame {
                MARK_FRAME
            } else {
                0
            };
            if mark != 0 {
                qemu_plugin_register_vcpu_insn_exec_cb(
                    insn,
                    on_marker,
                    CB_NO_REGS,
                    mark as *mut c_void,
                );
            }
            if state.profile {
                let slot = match state.index.get(&address) {
                    Some(&slot) => slot,
                    None => {
                        // A counter that starts when counting may already run: its snapshot
                        // is 0, so everything it counts belongs to the current window.
                        state.addresses.push((address, Box::leak(Box::new(0)), 0));
                        state.index.insert(address, state.addresses.len() - 1);
                        state.addresses.len() - 1
                    }
                };
                if let Some((_, counter, _)) = state.addresses.get_mut(slot) {
                    let counter: *mut u64 = &mut **counter;
                    qemu_plugin_register_vcpu_insn_exec_inline(
                        insn,
                        INLINE_ADD_U64,
                        counter.cast(),
                        1,
                    );
                }
            }
        }
    }
}

fn parse_address(text: &str) -> Option<u64> {
    let text = text.trim();
    match text.strip_prefix("0x") {
        Some(hex) => u64::from_str_radix(hex, 16).ok(),
        None => text.parse().ok(),
    }
}

/// Called by QEMU when the plugin is loaded.
///
/// # Safety
/// QEMU passes `argc` valid NUL-terminated strings in `argv`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn qemu_plugin_install(
    id: PluginId,
    _info: *const c_void,
    argc: c_int,
    argv: *const *const c_char,
) -> c_int {
    let mut state = State {
        start: u64::MAX,
        stop: u64::MAX,
        frame: u64::MAX,
        profile: false,
        since: [0; 3],
        frame_total: [0; 3],
        frames: 0,
        addresses: Vec::new(),
        index: HashMap::new(),
        frame_addresses: HashMap::new(),
    };
    for i in 0..usize::try_from(argc).unwrap_or(0) {
        // SAFETY: as the function's contract says.
        let arg = unsafe { CStr::from_ptr(*argv.add(i)) }.to_string_lossy();
        let Some((key, value)) = arg.split_once('=') else {
            continue;
        };
        match key {
            "start" => state.start = parse_address(value).unwrap_or(u64::MAX),
            "stop" => state.stop = parse_address(value).unwrap_or(u64::MAX),
            "frame" => state.frame = parse_address(value).unwrap_or(u64::MAX),
            "profile" => state.profile = value == "on" || value == "true",
            _ => {
                output(&format!("icount: unknown argument {key}\n"));
                return -1;
            }
        }
    }
    if let Ok(mut guard) = STATE.lock() {
        *guard = Some(state);
    }
    // SAFETY: registering callbacks with the id QEMU gave us.
    unsafe {
        qemu_plugin_register_vcpu_tb_trans_cb(id, on_translate);
    }
    0
}
