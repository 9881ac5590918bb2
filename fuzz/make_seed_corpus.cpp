// Writes the seed corpus of the LMS 2xx fuzzer: one file per telegram the link carries (every
// request, each kind of reply, scans in each unit), so the fuzzer starts past the CRC.
// Usage: make_seed_corpus DIR
#include <cstdio>
#include <fstream>
#include <string>

#include "hal/lms2xx/messages.hpp"
#include "hal/lms2xx/scan_telegram.hpp"

using namespace tofcomp::hal::lms2xx;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_seed_corpus DIR\n");
    return 2;
  }
  std::vector<Telegram> seeds = {reset_request(),
                                 switch_mode_request(OperatingMode::Baud500000),
                                 installation_mode_request(),
                                 values_request(),
                                 status_request(),
                                 type_request(),
                                 variant_request({180, 50}),
                                 configuration_request(),
                                 configure_request(ConfigurationBlock{})};
  const std::vector<std::uint8_t> ok{0x00}, accepted{0x01, 180, 0, 50, 0};
  seeds.push_back(make_reply(0xA0, ok, 0));
  seeds.push_back(make_reply(0xBB, accepted, 0));
  seeds.push_back(make_reply(0xF4, ConfigurationBlock{}.bytes(), 0));
  seeds.push_back(make_reply(0xB1, std::vector<std::uint8_t>(kStatusBytes, 0), 0));
  for (const auto units : {Units::Millimetre, Units::Centimetre}) {
    ScanTelegram scan;
    scan.units = units;
    for (int i = 0; i < 181; ++i) {
      scan.distance_codes.push_back(static_cast<std::uint16_t>(3000 + i));
      scan.flags.push_back(0);
    }
    seeds.push_back(Telegram{0x80, kScanReply, encode_scan_data(scan, MeasuringMode::Range8m)});
  }
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    auto bytes = encode_telegram(seeds[i]);
    bytes.insert(bytes.begin(), static_cast<std::uint8_t>(i * 7));  // the read-size byte
    std::ofstream out(std::string(argv[1]) + "/seed-" + std::to_string(i), std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
  }
  std::printf("%zu seeds written to %s\n", seeds.size(), argv[1]);
  return 0;
}
