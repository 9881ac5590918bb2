// PowerSwitch on a fake output; the libgpiod backend where there is no GPIO chip.
#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <cerrno>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "hal/gpio/gpiod_lines.hpp"
#include "hal/gpio/power_control.hpp"

namespace tofcomp::hal {
namespace {

struct OutputLog {
  std::vector<bool> sets;
  bool fail_next = false;
};

class FakeOutput : public GpioOutput {
 public:
  explicit FakeOutput(OutputLog& log) : log_(log) {}
  void set(bool active) override {
    if (log_.fail_next) throw GpioError("fake line: cannot set", EIO);
    log_.sets.push_back(active);
    value_ = active;
  }
  bool get() const override { return value_; }
  std::string describe() const override { return "fake line"; }

 private:
  OutputLog& log_;
  bool value_ = false;
};

TEST(PowerSwitch, SetsTheOutputAndRemembersTheState) {
  OutputLog log;
  PowerSwitch power(std::make_unique<FakeOutput>(log));
  EXPECT_FALSE(power.is_on());
  power.set(true);
  EXPECT_TRUE(power.is_on());
  power.set(false);
  power.set(true);
  EXPECT_EQ(log.sets, (std::vector<bool>{true, false, true}));
  EXPECT_TRUE(power.is_on());
  EXPECT_EQ(power.describe(), "fake line");
}

TEST(PowerSwitch, AFailedSetKeepsTheState) {
  OutputLog log;
  PowerSwitch power(std::make_unique<FakeOutput>(log), true);
  EXPECT_TRUE(power.is_on());
  log.fail_next = true;
  EXPECT_THROW(power.set(false), GpioError);
  EXPECT_TRUE(power.is_on());
  EXPECT_THROW(PowerSwitch(nullptr), core::InvalidInput);
}

TEST(GpiodLines, NonexistentChipIsAnErrorNamingChipAndLine) {
  const std::string chip = "gpiochip-tofcomp-test-missing";
  try {
    GpiodOutput output(chip, "17", false, false);
    FAIL() << "no exception";
  } catch (const GpioError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find(chip), std::string::npos) << what;
    EXPECT_NE(what.find("17"), std::string::npos) << what;
    EXPECT_NE(error.error_number(), 0);
  }
  try {
    GpiodEdgeSource source("/dev/gpiochip-tofcomp-test-missing", "SCANNER_PG", true);
    FAIL() << "no exception";
  } catch (const GpioError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("/dev/gpiochip-tofcomp-test-missing"), std::string::npos) << what;
    EXPECT_NE(what.find("SCANNER_PG"), std::string::npos) << what;
    EXPECT_NE(what.find("No such file or directory"), std::string::npos) << what;
  }
}

TEST(GpiodLines, FactoriesCheckTheConfigurationThenReportTheChip) {
  boost::asio::io_context io;
  const auto ignore = [](const GpioEdge&) {};
  EXPECT_THROW(make_power_switch(GpioLineConfig{"", "17", false}), core::InvalidInput);
  EXPECT_THROW(make_power_switch(GpioLineConfig{"gpiochip0", "", false}), core::InvalidInput);
  EXPECT_THROW(make_power_sense(io, GpioLineConfig{"", "17", false}, ignore), core::InvalidInput);

  const GpioLineConfig missing{"gpiochip-tofcomp-test-missing", "4", true};
  try {
    make_power_switch(missing);
    FAIL() << "no exception";
  } catch (const GpioError& error) {
    EXPECT_NE(std::string(error.what()).find(missing.chip), std::string::npos) << error.what();
  }
  try {
    make_power_sense(io, missing, ignore);
    FAIL() << "no exception";
  } catch (const GpioError& error) {
    EXPECT_NE(std::string(error.what()).find(missing.chip), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace tofcomp::hal
