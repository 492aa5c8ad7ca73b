// Runs microray's Pico firmware in rp2040js, headless, and reads the ST7789 panel off the
// SPI0 stream (`cargo xtask pico` calls it; see docs/pico.md).
//
//   node run.mjs FIRMWARE.elf BOOTROM.bin PANEL.out [MAX_CYCLES [CYCLES.out]]
//
// Boots the B1 bootrom's second stage (the PC at 0x10000000, as the emulator's own demo
// does), decodes the panel's commands (DC on GP16 low: a command; CS on GP17 low: the panel
// listens; CASET/RASET windows, RAMWR pixels, big-endian Rgb565), and times the render by
// the LED on GP25. Writes the panel's 240x240 pixels (2 bytes each, big-endian) to PANEL.out
// and prints one JSON line: the cycles at the LED's edges and what the stream held. With
// CYCLES.out, also the cycles spent at each flash address while the LED is lit (a float64
// per halfword of flash, for the profile of tracing against output).
import { readFileSync, writeFileSync } from 'node:fs';
import { Simulator } from 'rp2040js';

const [elfPath, bootromPath, outPath, maxArg, cyclesPath] = process.argv.slice(2);
if (!outPath) {
  console.error('usage: node run.mjs FIRMWARE.elf BOOTROM.bin PANEL.out [MAX_CYCLES]');
  process.exit(2);
}
const maxCycles = Number(maxArg ?? 20e9);

const PANEL = 240;
const FLASH = 0x10000000;
const [DC, CS, LED] = [16, 17, 25];

// The simulator's clock and chip; stepped here rather than by its timer loop.
const { clock, rp2040: mcu } = new Simulator();
const bootrom = readFileSync(bootromPath);
mcu.loadBootrom(new Uint32Array(bootrom.buffer, bootrom.byteOffset, bootrom.length / 4));

// The ELF's loadable segments, at their load addresses (the flash image a UF2 would hold).
const elf = readFileSync(elfPath);
const view = new DataView(elf.buffer, elf.byteOffset, elf.length);
const phoff = view.getUint32(0x1c, true);
const phentsize = view.getUint16(0x2a, true);
const phnum = view.getUint16(0x2c, true);
for (let i = 0; i < phnum; i++) {
  const at = phoff + i * phentsize;
  const type = view.getUint32(at, true);
  const offset = view.getUint32(at + 4, true);
  const paddr = view.getUint32(at + 12, true);
  const filesz = view.getUint32(at + 16, true);
  if (type !== 1 || filesz === 0) continue;
  if (paddr < FLASH || paddr + filesz > FLASH + mcu.flash.length) {
    console.error(`segment at 0x${paddr.toString(16)} is not in flash`);
    process.exit(1);
  }
  mcu.flash.set(elf.subarray(offset, offset + filesz), paddr - FLASH);
}
mcu.core.PC = FLASH;

// The panel: a window and a write position, filled by RAMWR's pixels.
const panel = new Uint8Array(PANEL * PANEL * 2);
let command = -1;
let args = [];
let window = { x0: 0, x1: PANEL - 1, y0: 0, y1: PANEL - 1 };
let x = 0;
let y = 0;
let pending = -1;
const stream = { bytes: 0, commands: 0, windows: 0, pixels: 0, outside: 0 };
const pin = (n) => mcu.gpio[n].outputValue;
mcu.spi[0].onTransmit = (value) => {
  mcu.spi[0].completeTransmit(0);
  if (pin(CS)) return; // not selected
  stream.bytes++;
  if (!pin(DC)) {
    command = value;
    args = [];
    pending = -1;
    stream.commands++;
    if (command === 0x2c) {
      x = window.x0;
      y = window.y0;
    }
    return;
  }
  if (command === 0x2a || command === 0x2b) {
    args.push(value);
    if (args.length === 4) {
      const lo = (args[0] << 8) | args[1];
      const hi = (args[2] << 8) | args[3];
      if (command === 0x2a) window = { ...window, x0: lo, x1: hi };
      else window = { ...window, y0: lo, y1: hi };
      stream.windows++;
    }
  } else if (command === 0x2c) {
    if (pending < 0) {
      pending = value;
      return;
    }
    if (x < PANEL && y < PANEL) {
      const i = (y * PANEL + x) * 2;
      panel[i] = pending;
      panel[i + 1] = value;
    } else {
      stream.outside++;
    }
    stream.pixels++;
    pending = -1;
    x++;
    if (x > window.x1) {
      x = window.x0;
      y++;
    }
  }
};

// The LED's edges, in cycles.
// (The listener hears every change of the pin's state, its set-up too: only the output's
// rises and falls count.)
const edges = [];
let led = false;
mcu.gpio[LED].addListener(() => {
  const high = pin(LED) && mcu.gpio[LED].outputEnable;
  if (high !== led) {
    led = high;
    edges.push({ high, cycles: mcu.core.cycles });
  }
});

const profile = cyclesPath ? new Float64Array(mcu.flash.length / 2) : null;
const cycleNanos = 1e9 / 125e6;
let idle = 0;
while (mcu.core.cycles < maxCycles) {
  if (edges.length >= 2 && !edges[edges.length - 1].high) break;
  if (mcu.core.waiting) {
    // Asleep (`wfi`): the clock runs to the next alarm, if there is one.
    const next = clock.nanosToNextAlarm;
    if (!(next > 0) || ++idle > 1000) break;
    clock.tick(next);
    mcu.core.cycles += Math.ceil(next / cycleNanos);
  } else {
    const pc = mcu.core.PC;
    const cycles = mcu.core.executeInstruction();
    clock.tick(cycles * cycleNanos);
    if (profile && led) {
      const at = (pc - FLASH) >>> 1;
      if (at < profile.length) profile[at] += cycles;
    }
  }
}
if (profile) writeFileSync(cyclesPath, new Uint8Array(profile.buffer));
if (process.env.PICO_DEBUG) console.error(`stopped: pc=0x${mcu.core.PC.toString(16)} waiting=${mcu.core.waiting} next=${clock.nanosToNextAlarm}`);
writeFileSync(outPath, panel);
const on = edges.find((e) => e.high);
const off = edges.find((e) => !e.high && on && e.cycles > on.cycles);
console.log(
  JSON.stringify({
    led_on: on?.cycles ?? null,
    led_off: off?.cycles ?? null,
    render_cycles: on && off ? off.cycles - on.cycles : null,
    total_cycles: mcu.core.cycles,
    ...stream,
  }),
);
