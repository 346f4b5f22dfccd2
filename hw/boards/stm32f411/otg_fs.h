// USB full-speed device on the STM32F411's OTG FS core (RM0383 chapter 22), FIFO (slave) mode:
// endpoint 0 for the chapter-9 requests of hw/usb, and the vendor interface's bulk OUT (0x01)
// and bulk IN (0x81) endpoints as a byte link with flow control in both directions.
#pragma once
#include <cstddef>
#include <cstdint>

#include "hw/boards/stm32f411/byte_ring.h"
#include "hw/usb/control.h"

namespace dg::stm32 {

class OtgFsDevice final : public usb::EndpointControl {
 public:
  // `serial` must outlive the device (the string descriptor points at it).
  explicit OtgFsDevice(const char* serial) : control_(*this, serial) {}

  // Pins, clock, core reset and configuration, then the pull-up on D+ (the host sees a device).
  // False when the core does not answer within its bounded waits (no USB clock: a broken board).
  bool start();
  // The OTG_FS interrupt.
  void irq();

  // The byte link: never blocks; returns how much was taken or read.
  size_t write(const uint8_t* data, size_t size);
  size_t read(uint8_t* data, size_t capacity);
  bool readable() const { return rx_.size() > 0; }
  // The host suspended the bus (USBSUSP) and has not woken it or reset it since.
  bool suspended() const { return suspended_; }

  // usb::EndpointControl
  void set_address(uint8_t address) override;
  void set_configured(bool configured) override;
  void set_halt(uint8_t endpoint_address, bool halt) override;
  bool halted(uint8_t endpoint_address) override;

 private:
  void bus_reset();
  void enumeration_done();
  void receive_status();
  void in_endpoint_interrupts();
  void out_endpoint_interrupts();
  void setup_received();
  void ep0_send_packet();
  void ep0_arm_out();
  void bulk_in_kick();
  void bulk_out_arm();
  void fifo_read(uint8_t* out, size_t count, ByteRing<256>* ring);
  // Flushes a transmit FIFO (0x10: all); false when the core does not finish within 1 ms.
  bool flush_tx_fifo(uint32_t number);

  usb::ControlRequests control_;
  uint8_t setup_[8] = {};
  const uint8_t* ep0_data_ = nullptr;
  uint16_t ep0_left_ = 0;
  bool ep0_zero_length_due_ = false;  // a reply shorter than asked and a multiple of 64 ends with one
  ByteRing<256> rx_;  // host to device, filled by the interrupt
  ByteRing<256> tx_;  // device to host, emptied by the interrupt
  volatile bool configured_ = false;
  volatile bool suspended_ = false;
  volatile bool in_busy_ = false;
  volatile bool out_armed_ = false;
  bool in_zero_length_due_ = false;  // the last IN packet was full and nothing followed it
  bool in_halted_ = false, out_halted_ = false;
};

}  // namespace dg::stm32
