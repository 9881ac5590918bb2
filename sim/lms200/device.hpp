// The device side of the LMS 2xx protocol: what an LMS 200 answers to each request, and the
// state it keeps (rate, operating mode, variant, configuration) and loses on a reset. Pure: bytes
// from the host in, bytes to send out; the pty server (sim/lms200/emulator.hpp) moves them.
//
// It answers as the listing says the device answers, so any host driver written to the listing
// can drive it: ACK then the reply for an accepted request; NAK for a bad CRC (the decoder drops
// such a frame), an unknown command or a wrong length; installation mode only with the
// password; configuration only in installation mode; a variant the device lacks refused.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hal/lms2xx/commands.hpp"
#include "hal/lms2xx/configuration_block.hpp"
#include "hal/lms2xx/scan_telegram.hpp"
#include "hal/lms2xx/telegram_decoder.hpp"
#include "sim/twin.hpp"

namespace tofcomp::sim::lms200 {

namespace protocol = tofcomp::hal::lms2xx;

struct DeviceIdentity {
  std::string type = "LMS200;30106";
  std::string firmware_version = "V02.10 ";  // 7 characters, as in the status block
  bool supports_500k = true;                 // RS-422 units; RS-232 ones refuse 500 kBd
};

// Something for the server to do after the bytes before it have gone out.
struct DeviceOutput {
  enum class Action { Send, SendScan, SwitchBaud, Restart };  // SendScan: a fresh 0xB0
  Action action = Action::Send;
  std::vector<std::uint8_t> bytes;  // for Send
  unsigned baud = 0;                // for SwitchBaud
};

class Lms200Device {
 public:
  explicit Lms200Device(DeviceIdentity identity = {});

  // Bytes from the host, at the device's current rate; the answers are appended to `out`.
  void receive(std::span<const std::uint8_t> bytes, std::vector<DeviceOutput>& out);
  // The rate changes once the reply to a rate switch has gone out (Action::SwitchBaud).
  void set_baud(unsigned baud) { baud_ = baud; }
  // The device restarts (reset request, power cycle, or a fault): state back to power-on.
  void restart();
  // The telegram the device sends when it has started (0x91).
  std::vector<std::uint8_t> power_on_telegram() const;
  // A 0xB0 telegram of `readings` (one per value of the current variant) in the configured
  // units and measuring mode; readings beyond the range become the reserved no-echo code.
  std::vector<std::uint8_t> scan_telegram(const std::vector<RangeReading>& readings) const;
  // What the twin must report for the current variant and configuration.
  ScannerOutput scanner_output(const ScannerOutput& base) const;

  unsigned baud() const { return baud_; }
  bool streaming() const { return streaming_; }
  bool installation_mode() const { return installation_mode_; }
  const protocol::Variant& variant() const { return variant_; }
  const protocol::ConfigurationBlock& configuration() const { return configuration_; }
  const protocol::DecoderCounters& decoder_counters() const { return decoder_.counters(); }
  std::uint64_t naks_sent() const { return naks_sent_; }

 private:
  DeviceIdentity identity_;
  protocol::TelegramDecoder decoder_{protocol::Sender::Host};
  unsigned baud_ = protocol::kPowerOnBaud;
  bool streaming_ = false;
  bool installation_mode_ = false;
  protocol::Variant variant_{};
  protocol::ConfigurationBlock configuration_{};
  std::uint8_t status_byte_ = 0x00;
  std::uint64_t naks_sent_ = 0;

  void answer(const protocol::Telegram& request, std::vector<DeviceOutput>& out);
  void reply(std::uint8_t code, std::span<const std::uint8_t> data,
             std::vector<DeviceOutput>& out) const;
  void nak(std::vector<DeviceOutput>& out);
  void switch_mode(std::span<const std::uint8_t> data, std::vector<DeviceOutput>& out);
  std::vector<std::uint8_t> status_block() const;
};

}  // namespace tofcomp::sim::lms200
