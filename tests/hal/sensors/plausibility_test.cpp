// CheckedSensor with a scripted backend and an injected clock: range, rate and staleness.
#include "hal/sensors/plausibility.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <deque>
#include <memory>

#include "core/error.hpp"

namespace tofcomp::hal {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::system_clock;

// Returns the scripted readings in order (the time field is ignored by CheckedSensor).
class ScriptedSensor : public TemperatureSensor {
 public:
  explicit ScriptedSensor(std::deque<TemperatureReading>& script) : script_(script) {}
  TemperatureReading read() override {
    TemperatureReading next = script_.front();
    script_.pop_front();
    return next;
  }
  std::string describe() const override { return "scripted"; }

 private:
  std::deque<TemperatureReading>& script_;
};

class Plausibility : public ::testing::Test {
 protected:
  CheckedSensor make(PlausibilityLimits limits = {}) {
    return CheckedSensor(std::make_unique<ScriptedSensor>(script_), limits,
                         [this] { return now_; });
  }
  void feed(double celsius) { script_.push_back(valid_reading({}, celsius)); }
  void fail(ReadingValidity validity, const std::string& detail) {
    script_.push_back(invalid_reading({}, validity, detail));
  }

  std::deque<TemperatureReading> script_;
  Clock::time_point now_ = Clock::time_point(1700000000s);
};

TEST_F(Plausibility, PassesValidReadingsStampedWithTheClock) {
  CheckedSensor sensor = make();
  feed(21.5);
  const TemperatureReading reading = sensor.read();
  ASSERT_TRUE(reading.valid()) << reading.detail;
  EXPECT_EQ(reading.celsius, 21.5);
  EXPECT_EQ(reading.time, now_);
}

TEST_F(Plausibility, OutOfRangeIsImplausible) {
  CheckedSensor sensor = make();  // -40 .. 125 °C
  for (const double t : {-40.5, 125.5, 150.0, -273.15}) {
    feed(t);
    const TemperatureReading reading = sensor.read();
    EXPECT_EQ(reading.validity, ReadingValidity::Implausible) << t;
    EXPECT_TRUE(std::isnan(reading.celsius));
    EXPECT_NE(reading.detail.find("outside"), std::string::npos) << reading.detail;
  }
  for (const double t : {-40.0, 125.0}) {
    feed(t);
    now_ += 1h;  // far enough apart for the rate check to allow the step
    EXPECT_TRUE(sensor.read().valid()) << t;
  }
}

TEST_F(Plausibility, ImpossibleJumpIsImplausibleAndDoesNotReplaceTheLastValid) {
  PlausibilityLimits limits;
  limits.max_rate_c_per_s = 1.0;
  limits.jump_allowance_c = 0.5;
  CheckedSensor sensor = make(limits);

  feed(20.0);
  ASSERT_TRUE(sensor.read().valid());
  now_ += 2s;  // at most 0.5 + 1.0 * 2 = 2.5 °C
  feed(22.4);
  ASSERT_TRUE(sensor.read().valid());

  now_ += 1s;  // at most 1.5 °C from 22.4
  feed(30.0);
  const TemperatureReading jump = sensor.read();
  EXPECT_EQ(jump.validity, ReadingValidity::Implausible);
  EXPECT_TRUE(std::isnan(jump.celsius));
  EXPECT_NE(jump.detail.find("jump"), std::string::npos) << jump.detail;

  // Compared against 22.4 from 2 s ago (2.5 °C allowed), not against the rejected 30.0 (which
  // would allow 1.5 °C and reject it).
  now_ += 1s;
  feed(24.8);
  EXPECT_TRUE(sensor.read().valid());
  now_ += 1s;
  feed(20.0);  // 4.8 °C down in 1 s
  EXPECT_EQ(sensor.read().validity, ReadingValidity::Implausible);
}

TEST_F(Plausibility, QuantizationStepsWithinTheAllowanceAreAccepted) {
  CheckedSensor sensor = make();
  feed(20.0);
  ASSERT_TRUE(sensor.read().valid());
  feed(20.0625);  // the same instant: one DS18B20/TMP102 step
  EXPECT_TRUE(sensor.read().valid());
}

TEST_F(Plausibility, FailuresKeepTheirValidityUntilMaxAgeThenTurnStale) {
  PlausibilityLimits limits;
  limits.max_age = std::chrono::duration<double>(10.0);
  CheckedSensor sensor = make(limits);

  feed(20.0);
  ASSERT_TRUE(sensor.read().valid());

  now_ += 5s;
  fail(ReadingValidity::ReadError, "crc NO");
  const TemperatureReading early = sensor.read();
  EXPECT_EQ(early.validity, ReadingValidity::ReadError);
  EXPECT_EQ(early.detail, "crc NO");

  now_ += 5s;  // exactly max_age: not yet older
  fail(ReadingValidity::ReadError, "crc NO");
  EXPECT_EQ(sensor.read().validity, ReadingValidity::ReadError);

  now_ += 1s;
  fail(ReadingValidity::ReadError, "crc NO");
  const TemperatureReading stale = sensor.read();
  EXPECT_EQ(stale.validity, ReadingValidity::Stale);
  EXPECT_TRUE(std::isnan(stale.celsius));
  EXPECT_NE(stale.detail.find("crc NO"), std::string::npos) << stale.detail;
  EXPECT_NE(stale.detail.find("read-error"), std::string::npos) << stale.detail;

  now_ += 1s;
  fail(ReadingValidity::Missing, "unplugged");
  EXPECT_EQ(sensor.read().validity, ReadingValidity::Stale);

  // A valid reading ends staleness (the rate allows a step after 12 s).
  now_ += 1s;
  feed(25.0);
  EXPECT_TRUE(sensor.read().valid());
  fail(ReadingValidity::ReadError, "crc NO");
  EXPECT_EQ(sensor.read().validity, ReadingValidity::ReadError);
}

TEST_F(Plausibility, ImplausibleReadingsTurnStaleToo) {
  CheckedSensor sensor = make();
  feed(20.0);
  ASSERT_TRUE(sensor.read().valid());
  now_ += 11s;
  feed(500.0);
  EXPECT_EQ(sensor.read().validity, ReadingValidity::Stale);
}

TEST_F(Plausibility, NothingIsStaleBeforeTheFirstValidReading) {
  CheckedSensor sensor = make();
  fail(ReadingValidity::Missing, "no device");
  EXPECT_EQ(sensor.read().validity, ReadingValidity::Missing);
  now_ += 1h;
  fail(ReadingValidity::Missing, "no device");
  EXPECT_EQ(sensor.read().validity, ReadingValidity::Missing);
}

TEST_F(Plausibility, RejectsUnusableLimits) {
  const auto rejects = [this](PlausibilityLimits limits) {
    EXPECT_THROW(make(limits), core::InvalidInput);
  };
  PlausibilityLimits limits;
  limits.min_c = 50;
  limits.max_c = 50;
  rejects(limits);
  limits = {};
  limits.max_c = NAN;
  rejects(limits);
  limits = {};
  limits.max_rate_c_per_s = 0;
  rejects(limits);
  limits = {};
  limits.jump_allowance_c = -1;
  rejects(limits);
  limits = {};
  limits.max_age = std::chrono::duration<double>(0.0);
  rejects(limits);
  EXPECT_THROW(CheckedSensor(nullptr), core::InvalidInput);
}

TEST(TemperatureReading, InvalidReadingsCarryNoNumber) {
  const TemperatureReading nan_as_valid = valid_reading({}, NAN);
  EXPECT_EQ(nan_as_valid.validity, ReadingValidity::ReadError);
  EXPECT_TRUE(std::isnan(nan_as_valid.celsius));
  EXPECT_THROW(invalid_reading({}, ReadingValidity::Valid, "x"), core::InvalidInput);
  EXPECT_EQ(to_string(ReadingValidity::Stale), "stale");
  EXPECT_EQ(to_string(ReadingValidity::ReadError), "read-error");
}

}  // namespace
}  // namespace tofcomp::hal
