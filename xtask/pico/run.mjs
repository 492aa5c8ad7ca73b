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
//
// With MICRORAY_PANEL=ssd1306 the panel is instead a 128x64 one-bit SSD1306 at 0x3C on I2C0
// (firmware/pico/src/bin/oled.rs): its command and data stream is decoded (horizontal and
// page addressing, the column and page windows) into its display RAM, and PANEL.out gets
// one byte a pixel, 0 or 1, rows from the top, as the driver lays the picture out (column x,
// page y / 8, bit y % 8).
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

// The SSD1306: its display RAM, pages of 128 columns, each byte 8 rows (bit 0 the top).
const oled = process.env.MICRORAY_PANEL === 'ssd1306';
const [OLED_W, OLED_PAGES, OLED_ADDRESS] = [128, 8, 0x3c];
const gddram = new Uint8Array(OLED_W * OLED_PAGES);
const i2cStream = { transactions: 0, commands: 0, data: 0, unknown: 0 };
if (oled) {
  // Argument bytes of each command with any (the rest take none).
  const argCount = (c) => {
    if ([0x20, 0x81, 0x8d, 0xa8, 0xd3, 0xd5, 0xd9, 0xda, 0xdb].includes(c)) return 1;
    if (c === 0x21 || c === 0x22) return 2;
    return 0;
  };
  let mode = 2; // page addressing, the controller's reset state
  let [col, colStart, colEnd] = [0, 0, OLED_W - 1];
  let [page, pageStart, pageEnd] = [0, 0, OLED_PAGES - 1];
  let addressed = false;
  let control = -1; // the transaction's control byte: 0x00 commands, 0x40 data
  let command = [];
  const i2c = mcu.i2c[0];
  i2c.onStart = () => i2c.completeStart();
  i2c.onConnect = (address) => {
    addressed = address === OLED_ADDRESS;
    control = -1;
    if (addressed) i2cStream.transactions++;
    i2c.completeConnect(addressed);
  };
  i2c.onReadByte = () => i2c.completeRead(0xff);
  i2c.onStop = () => i2c.completeStop();
  const run = (c) => {
    const [op, a, b] = c;
    i2cStream.commands++;
    if (op === 0x20) mode = a & 3;
    else if (op === 0x21) [colStart, colEnd, col] = [a & 0x7f, b & 0x7f, a & 0x7f];
    else if (op === 0x22) [pageStart, pageEnd, page] = [a & 7, b & 7, a & 7];
    else if (op >= 0xb0 && op <= 0xb7) page = op & 7;
    else if (op <= 0x0f) col = (col & 0xf0) | op;
    else if (op >= 0x10 && op <= 0x1f) col = (col & 0x0f) | ((op & 0x0f) << 4);
  };
  i2c.onWriteByte = (value) => {
    i2c.completeWrite(addressed);
    if (!addressed) return;
    if (control < 0) {
      control = value;
      return;
    }
    if (control === 0x00 || control === 0x80) {
      command.push(value);
      if (command.length === 1 + argCount(command[0])) {
        run(command);
        command = [];
      }
    } else if (control === 0x40) {
      i2cStream.data++;
      gddram[page * OLED_W + col] = value;
      if (col < colEnd) col++;
      else {
        col = colStart;
        if (mode === 0) page = page < pageEnd ? page + 1 : pageStart;
      }
    } else {
      i2cStream.unknown++;
    }
  };
}

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
if (oled) {
  const pixels = new Uint8Array(OLED_W * OLED_PAGES * 8);
  for (let y = 0; y < OLED_PAGES * 8; y++) {
    for (let x = 0; x < OLED_W; x++) {
      pixels[y * OLED_W + x] = (gddram[(y >> 3) * OLED_W + x] >> (y & 7)) & 1;
    }
  }
  writeFileSync(outPath, pixels);
} else {
  writeFileSync(outPath, panel);
}
const on = edges.find((e) => e.high);
const off = edges.find((e) => !e.high && on && e.cycles > on.cycles);
console.log(
  JSON.stringify({
    led_on: on?.cycles ?? null,
    led_off: off?.cycles ?? null,
    render_cycles: on && off ? off.cycles - on.cycles : null,
    total_cycles: mcu.core.cycles,
    ...(oled ? i2cStream : stream),
  }),
);
