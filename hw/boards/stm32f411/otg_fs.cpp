// Register offsets and bits are from RM0383 section 22.16 (OTG_FS registers); the sequences
// follow its programming model (22.17.3 device initialization, 22.17.5 device programming model).
// The core's 1.25 KB of FIFO RAM is split as: receive 128 words, endpoint 0 transmit 32, bulk IN
// transmit 64.
#include "hw/boards/stm32f411/otg_fs.h"

#include "hw/boards/stm32f411/registers.h"
#include "hw/usb/descriptors.h"

namespace dg::stm32 {

namespace {

constexpr uint32_t kOtg = 0x50000000;
// Global registers.
constexpr uint32_t kGahbcfg = kOtg + 0x008, kGusbcfg = kOtg + 0x00C, kGrstctl = kOtg + 0x010,
                   kGintsts = kOtg + 0x014, kGintmsk = kOtg + 0x018, kGrxstsp = kOtg + 0x020,
                   kGrxfsiz = kOtg + 0x024, kDieptxf0 = kOtg + 0x028, kGccfg = kOtg + 0x038,
                   kDieptxf1 = kOtg + 0x104;
// Device registers.
constexpr uint32_t kDcfg = kOtg + 0x800, kDctl = kOtg + 0x804, kDiepmsk = kOtg + 0x810, kDoepmsk = kOtg + 0x814,
                   kDaint = kOtg + 0x818, kDaintmsk = kOtg + 0x81C;
constexpr uint32_t diepctl(uint32_t ep) { return kOtg + 0x900 + 0x20 * ep; }
constexpr uint32_t diepint(uint32_t ep) { return kOtg + 0x908 + 0x20 * ep; }
constexpr uint32_t dieptsiz(uint32_t ep) { return kOtg + 0x910 + 0x20 * ep; }
constexpr uint32_t doepctl(uint32_t ep) { return kOtg + 0xB00 + 0x20 * ep; }
constexpr uint32_t doepint(uint32_t ep) { return kOtg + 0xB08 + 0x20 * ep; }
constexpr uint32_t doeptsiz(uint32_t ep) { return kOtg + 0xB10 + 0x20 * ep; }
constexpr uint32_t kPcgcctl = kOtg + 0xE00;
constexpr uint32_t fifo(uint32_t ep) { return kOtg + 0x1000 + 0x1000 * ep; }

// GINTSTS / GINTMSK bits.
constexpr uint32_t kRxflvl = 1u << 4, kUsbsusp = 1u << 11, kUsbrst = 1u << 12, kEnumdne = 1u << 13,
                   kIepint = 1u << 18, kOepint = 1u << 19, kWkupint = 1u << 31;
// DIEPCTLx / DOEPCTLx bits.
constexpr uint32_t kUsbaep = 1u << 15, kStall = 1u << 21, kCnak = 1u << 26, kSnak = 1u << 27,
                   kSd0pid = 1u << 28, kEpdis = 1u << 30, kEpena = 1u << 31;
constexpr uint32_t kBulk = 2u << 18;
// DxEPINTx bits.
constexpr uint32_t kXfrc = 1u << 0, kEpdisd = 1u << 1, kStup = 1u << 3;
// DCTL: soft disconnect (the D+ pull-up off while set).
constexpr uint32_t kSdis = 1u << 1;
// Transfer size: one packet.
constexpr uint32_t kOnePacket = 1u << 19;
constexpr uint32_t kSetupCount3 = 3u << 29;

constexpr uint32_t kBulkEp = 1;  // endpoint number of both bulk endpoints
constexpr uint32_t kPacket = usb::kBulkPacketSize;

void delay_cycles(uint32_t cycles) {
  const uint32_t start = reg(kDwtCyccnt);
  while (reg(kDwtCyccnt) - start < cycles) {
  }
}

// Every wait on the core is bounded: a core that never answers (no clock, a broken board) is a
// false from here, not a hang. 1 ms is far beyond what each step takes.
constexpr uint32_t kCoreWaitCycles = kSysclkHz / 1000;

// Waits until (register & mask) is nonzero when `set`, zero otherwise.
bool wait_for(uint32_t address, uint32_t mask, bool set) {
  const uint32_t start = reg(kDwtCyccnt);
  while (((reg(address) & mask) != 0) != set) {
    if (reg(kDwtCyccnt) - start > kCoreWaitCycles) return false;
  }
  return true;
}

}  // namespace

bool OtgFsDevice::start() {
  // PA11 (D-) and PA12 (D+): alternate function 10, very high speed.
  reg(kRccAhb1Enr) |= 1u << 0;
  reg(kGpioA + kModer) = (reg(kGpioA + kModer) & ~(0xFu << 22)) | (0xAu << 22);
  reg(kGpioA + kOspeedr) |= 0xFu << 22;
  reg(kGpioA + kAfrh) = (reg(kGpioA + kAfrh) & ~(0xFFu << 12)) | (0xAAu << 12);
  reg(kRccAhb2Enr) |= 1u << 7;  // OTGFSEN
  (void)static_cast<uint32_t>(reg(kRccAhb2Enr));  // read back: the clock is on before the first access

  // Core soft reset once the AHB side is idle.
  if (!wait_for(kGrstctl, 1u << 31, true)) return false;
  reg(kGrstctl) |= 1u;
  if (!wait_for(kGrstctl, 1u, false)) return false;
  // The D+ pull-up stays off until the core is set up: DCTL comes out of reset connected, and a
  // host that sees the device before its FIFOs and interrupts exist resets and enumerates it into
  // a core that cannot answer yet.
  reg(kDctl) |= kSdis;
  // Full-speed PHY, turnaround time 6 (AHB at 32 MHz or more, RM0383 table 133), forced device
  // mode, which takes effect after 25 ms.
  reg(kGusbcfg) = (1u << 6) | (6u << 10) | (1u << 30);
  delay_cycles(kSysclkHz / 40);
  // Transceiver on; VBUS is not wired to PA9 on the Black Pill, so no VBUS sensing.
  reg(kGccfg) = (1u << 16) | (1u << 21);
  reg(kPcgcctl) = 0;
  reg(kDcfg) = 3u;  // full speed
  // FIFO RAM, in 32-bit words.
  reg(kGrxfsiz) = 128;
  reg(kDieptxf0) = (32u << 16) | 128u;
  reg(kDieptxf1) = (64u << 16) | 160u;
  if (!flush_tx_fifo(0x10)) return false;  // all
  reg(kGrstctl) = 1u << 4;  // RXFFLSH
  if (!wait_for(kGrstctl, 1u << 4, false)) return false;
  reg(kDiepmsk) = kXfrc;
  reg(kDoepmsk) = kXfrc | kStup;
  reg(kGintsts) = 0xFFFFFFFF;
  reg(kGintmsk) = kRxflvl | kUsbsusp | kUsbrst | kEnumdne | kIepint | kOepint | kWkupint;
  reg(kGahbcfg) = 1u;  // global interrupt enable
  irq_enable(kIrqOtgFs, 2);
  reg(kDctl) &= ~kSdis;  // leave soft disconnect: the pull-up on D+ goes on
  return true;
}

bool OtgFsDevice::flush_tx_fifo(uint32_t number) {
  reg(kGrstctl) = (number << 6) | (1u << 5);
  return wait_for(kGrstctl, 1u << 5, false);
}

void OtgFsDevice::irq() {
  const uint32_t pending = reg(kGintsts) & reg(kGintmsk);
  if (pending & kUsbrst) {
    reg(kGintsts) = kUsbrst;
    suspended_ = false;
    bus_reset();
  }
  if (pending & kEnumdne) {
    reg(kGintsts) = kEnumdne;
    enumeration_done();
  }
  if (pending & kRxflvl) receive_status();  // may repeat while the receive FIFO has entries
  if (pending & kOepint) out_endpoint_interrupts();
  if (pending & kIepint) in_endpoint_interrupts();
  // Suspend: the host has stopped listening (the firmware pauses a scan and stops a jog); a
  // resume signal or a bus reset ends it. The board draws little, so it stays powered.
  if (pending & kUsbsusp) {
    reg(kGintsts) = kUsbsusp;
    suspended_ = true;
  }
  if (pending & kWkupint) {
    reg(kGintsts) = kWkupint;
    suspended_ = false;
  }
}

void OtgFsDevice::bus_reset() {
  reg(kDctl) &= ~1u;  // no remote wake-up signalling
  (void)flush_tx_fifo(0x10);
  for (uint32_t ep = 0; ep <= kBulkEp; ++ep) {
    reg(doepctl(ep)) |= kSnak;
    reg(diepint(ep)) = 0xFF;
    reg(doepint(ep)) = 0xFF;
  }
  reg(kDaintmsk) = (1u << 0) | (1u << 16);  // endpoint 0 both ways
  reg(kDcfg) &= ~(0x7Fu << 4);               // address 0
  control_.bus_reset();
  configured_ = false;
  in_busy_ = out_armed_ = false;
  in_zero_length_due_ = false;
  in_halted_ = out_halted_ = false;
  ep0_left_ = 0;
  ep0_zero_length_due_ = false;
  tx_.drop();  // half-sent frames: the link sends its frames again to the new session
  ep0_arm_out();
}

void OtgFsDevice::enumeration_done() {
  reg(diepctl(0)) &= ~3u;   // MPSIZ 0: 64-byte packets on endpoint 0
  reg(kDctl) |= 1u << 8;    // CGINAK
  ep0_arm_out();
}

void OtgFsDevice::ep0_arm_out() {
  reg(doeptsiz(0)) = kSetupCount3 | kOnePacket | 64u;
  reg(doepctl(0)) |= kEpena | kCnak;
}

void OtgFsDevice::fifo_read(uint8_t* out, size_t count, ByteRing<256>* ring) {
  // The FIFO register itself (on the host, the fake chip's proxy for it), read once a word.
  decltype(auto) rx = reg(fifo(0));  // every endpoint's OUT data comes through one FIFO
  for (size_t i = 0; i < count; i += 4) {
    const uint32_t word = rx;
    for (size_t b = 0; b < 4 && i + b < count; ++b) {
      const uint8_t byte = static_cast<uint8_t>(word >> (8 * b));
      if (ring != nullptr) ring->push_byte(byte);
      else if (out != nullptr) out[i + b] = byte;
    }
  }
}

void OtgFsDevice::receive_status() {
  const uint32_t status = reg(kGrxstsp);
  const uint32_t ep = status & 0xF;
  const uint32_t count = (status >> 4) & 0x7FF;
  const uint32_t packet_status = (status >> 17) & 0xF;
  switch (packet_status) {
    case 6:  // SETUP data packet: 8 bytes
      fifo_read(setup_, count < 8 ? count : 8, nullptr);
      break;
    case 2:  // OUT data packet
      if (ep == kBulkEp) {
        fifo_read(nullptr, count, &rx_);  // bulk_out_arm() made sure it fits
      } else {
        fifo_read(nullptr, count, nullptr);  // endpoint 0 takes no OUT data: only the status stage
      }
      break;
    default:  // global OUT NAK, OUT or SETUP transfer completed: no data to pop
      break;
  }
}

void OtgFsDevice::out_endpoint_interrupts() {
  const uint32_t endpoints = reg(kDaint) >> 16;
  if (endpoints & 1u) {
    const uint32_t flags = reg(doepint(0));
    reg(doepint(0)) = flags;
    if (flags & kStup) setup_received();
    else if (flags & kXfrc) ep0_arm_out();
  }
  if (endpoints & (1u << kBulkEp)) {
    const uint32_t flags = reg(doepint(kBulkEp));
    reg(doepint(kBulkEp)) = flags;
    if (flags & kXfrc) {
      out_armed_ = false;
      bulk_out_arm();  // or leave it NAKing until read() makes room
    }
  }
}

void OtgFsDevice::in_endpoint_interrupts() {
  const uint32_t endpoints = reg(kDaint) & 0xFFFF;
  if (endpoints & 1u) {
    const uint32_t flags = reg(diepint(0));
    reg(diepint(0)) = flags;
    if ((flags & kXfrc) && (ep0_left_ > 0 || ep0_zero_length_due_)) ep0_send_packet();
  }
  if (endpoints & (1u << kBulkEp)) {
    const uint32_t flags = reg(diepint(kBulkEp));
    reg(diepint(kBulkEp)) = flags;
    if (flags & kXfrc) {
      in_busy_ = false;
      bulk_in_kick();
    }
  }
}

void OtgFsDevice::setup_received() {
  const usb::Setup request = usb::parse_setup(setup_);
  const usb::ControlReply reply = control_.setup(request);
  ep0_arm_out();  // for the status stage and the next SETUP
  switch (reply.kind) {
    case usb::ControlReply::kStall:
      // The core clears endpoint 0's stall by itself when the next SETUP arrives.
      reg(diepctl(0)) |= kStall;
      reg(doepctl(0)) |= kStall;
      ep0_left_ = 0;
      break;
    case usb::ControlReply::kNoData:
      ep0_data_ = nullptr;
      ep0_left_ = 0;
      ep0_zero_length_due_ = true;  // the status stage
      ep0_send_packet();
      break;
    case usb::ControlReply::kData:
      ep0_data_ = reply.data;
      ep0_left_ = reply.size;
      ep0_zero_length_due_ = reply.size < request.length && reply.size % usb::kMaxPacketSize0 == 0;
      ep0_send_packet();
      break;
  }
}

void OtgFsDevice::ep0_send_packet() {
  const uint32_t size = ep0_left_ < usb::kMaxPacketSize0 ? ep0_left_ : usb::kMaxPacketSize0;
  if (size == 0) ep0_zero_length_due_ = false;
  reg(dieptsiz(0)) = kOnePacket | size;
  reg(diepctl(0)) |= kEpena | kCnak;
  decltype(auto) tx = reg(fifo(0));
  for (uint32_t i = 0; i < size; i += 4) {
    uint32_t word = 0;
    for (uint32_t b = 0; b < 4 && i + b < size; ++b) word |= uint32_t{ep0_data_[i + b]} << (8 * b);
    tx = word;
  }
  ep0_data_ += size;
  ep0_left_ = static_cast<uint16_t>(ep0_left_ - size);
}

void OtgFsDevice::set_address(uint8_t address) {
  // This core takes the new address at once and answers with it only after the status stage.
  reg(kDcfg) = (reg(kDcfg) & ~(0x7Fu << 4)) | (uint32_t{address} << 4);
}

void OtgFsDevice::set_configured(bool configured) {
  if (configured) {
    reg(diepctl(kBulkEp)) = kPacket | kUsbaep | kBulk | (1u << 22) /* TX FIFO 1 */ | kSd0pid | kSnak;
    reg(doepctl(kBulkEp)) = kPacket | kUsbaep | kBulk | kSd0pid | kSnak;
    reg(kDaintmsk) |= (1u << kBulkEp) | (1u << (16 + kBulkEp));
    in_busy_ = out_armed_ = false;
    in_halted_ = out_halted_ = false;
    configured_ = true;
    bulk_out_arm();
    bulk_in_kick();
    return;
  }
  configured_ = false;
  reg(kDaintmsk) &= ~((1u << kBulkEp) | (1u << (16 + kBulkEp)));
  if (reg(diepctl(kBulkEp)) & kEpena) reg(diepctl(kBulkEp)) |= kSnak | kEpdis;
  if (reg(doepctl(kBulkEp)) & kEpena) reg(doepctl(kBulkEp)) |= kSnak;
  reg(diepctl(kBulkEp)) &= ~kUsbaep;
  reg(doepctl(kBulkEp)) &= ~kUsbaep;
  (void)flush_tx_fifo(1);
  in_busy_ = out_armed_ = false;
}

void OtgFsDevice::set_halt(uint8_t endpoint_address, bool halt) {
  const bool in = (endpoint_address & 0x80) != 0;
  const uint32_t control = in ? diepctl(kBulkEp) : doepctl(kBulkEp);
  if (halt && in && (reg(control) & kEpena) != 0) {
    // A packet may sit in the IN FIFO: NAK and disable the endpoint first, wait for the core to
    // say it is disabled, then flush (RM0383 22.17.6, stalling a non-isochronous IN endpoint).
    reg(control) |= kSnak | kEpdis | kStall;
    (void)wait_for(diepint(kBulkEp), kEpdisd, true);
    reg(diepint(kBulkEp)) = kEpdisd;
    (void)flush_tx_fifo(1);
    in_busy_ = false;
  } else if (halt) {
    reg(control) |= kStall;
  } else {
    // Clearing a halt resets the data toggle to DATA0 (USB 2.0 9.4.5).
    reg(control) = (reg(control) & ~kStall) | kSd0pid;
  }
  (in ? in_halted_ : out_halted_) = halt;
  if (!halt) {
    if (in) {
      in_busy_ = false;
      (void)flush_tx_fifo(1);
      bulk_in_kick();
    } else {
      out_armed_ = false;
      bulk_out_arm();
    }
  }
}

bool OtgFsDevice::halted(uint8_t endpoint_address) { return (endpoint_address & 0x80) ? in_halted_ : out_halted_; }

void OtgFsDevice::bulk_out_arm() {
  if (!configured_ || out_armed_ || out_halted_ || rx_.free_space() < kPacket) return;
  reg(doeptsiz(kBulkEp)) = kOnePacket | kPacket;
  reg(doepctl(kBulkEp)) |= kEpena | kCnak;
  out_armed_ = true;
}

void OtgFsDevice::bulk_in_kick() {
  if (!configured_ || in_busy_ || in_halted_) return;
  uint32_t size = static_cast<uint32_t>(tx_.size());
  if (size == 0 && !in_zero_length_due_) return;
  if (size > kPacket) size = kPacket;
  // A full packet tells the host more follows; when nothing does, a zero-length packet ends the
  // host's transfer so the bytes reach it now.
  in_zero_length_due_ = size == kPacket;
  reg(dieptsiz(kBulkEp)) = kOnePacket | size;
  reg(diepctl(kBulkEp)) |= kEpena | kCnak;
  decltype(auto) fifo_in = reg(fifo(kBulkEp));
  uint8_t packet[kPacket];
  tx_.pop(packet, size);
  for (uint32_t i = 0; i < size; i += 4) {
    uint32_t word = 0;
    for (uint32_t b = 0; b < 4 && i + b < size; ++b) word |= uint32_t{packet[i + b]} << (8 * b);
    fifo_in = word;
  }
  in_busy_ = true;
}

size_t OtgFsDevice::write(const uint8_t* data, size_t size) {
  if (!configured_) return 0;  // no host: the link keeps its frames and sends them later
  const size_t taken = tx_.push(data, size);
  CriticalSection masked;
  bulk_in_kick();
  return taken;
}

size_t OtgFsDevice::read(uint8_t* data, size_t capacity) {
  const size_t n = rx_.pop(data, capacity);
  if (n > 0 && !out_armed_) {
    CriticalSection masked;
    bulk_out_arm();
  }
  return n;
}

}  // namespace dg::stm32
