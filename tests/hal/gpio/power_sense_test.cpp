// PowerSense inside a real io_context, driven by a fake edge source on a pipe: each byte
// written ('r' rising, 'f' falling) is one edge.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cerrno>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "hal/gpio/power_control.hpp"

namespace tofcomp::hal {
namespace {

using namespace std::chrono_literals;

// What the fake saw, kept outside it since PowerSense owns the source.
struct PipeLog {
  int write_fd = -1;
  int reads = 0;         // calls of read_edges
  int close_result = 1;  // the result of closing the read end (0: it was still open)
  int close_errno = 0;
};

class PipeEdgeSource : public GpioEdgeSource {
 public:
  explicit PipeEdgeSource(PipeLog& log) : log_(log) {
    int fds[2];
    if (::pipe2(fds, O_NONBLOCK | O_CLOEXEC) != 0) throw std::runtime_error("pipe2 failed");
    read_fd_ = fds[0];
    log_.write_fd = fds[1];
  }
  ~PipeEdgeSource() override {
    log_.close_result = ::close(read_fd_);
    log_.close_errno = errno;
    ::close(log_.write_fd);
  }
  int event_fd() const override { return read_fd_; }
  std::vector<GpioEdge> read_edges() override {
    ++log_.reads;
    std::vector<GpioEdge> edges;
    char buffer[64];
    for (;;) {
      const ssize_t n = ::read(read_fd_, buffer, sizeof buffer);
      if (n <= 0) break;
      for (ssize_t i = 0; i < n; ++i) {
        if (buffer[i] == 'x') throw GpioError("fake source: read failed", EIO);
        level_ = buffer[i] == 'r';
        edges.push_back(GpioEdge{level_, std::chrono::nanoseconds(++count_)});
      }
    }
    return edges;
  }
  bool level() const override { return level_; }
  std::string describe() const override { return "fake pipe line"; }

 private:
  PipeLog& log_;
  int read_fd_ = -1;
  bool level_ = false;
  std::int64_t count_ = 0;
};

void send(const PipeLog& log, const std::string& edges) {
  ASSERT_EQ(::write(log.write_fd, edges.data(), edges.size()), static_cast<ssize_t>(edges.size()));
}

TEST(PowerSense, DeliversEdgesInOrderOnTheIoContext) {
  boost::asio::io_context io;
  PipeLog log;
  std::vector<GpioEdge> seen;
  PowerSense sense(io, std::make_unique<PipeEdgeSource>(log), [&](const GpioEdge& edge) {
    seen.push_back(edge);
    if (seen.size() == 5) io.stop();
  });

  send(log, "rfr");
  boost::asio::steady_timer later(io, 20ms);
  later.async_wait([&](const boost::system::error_code&) { send(log, "ff"); });
  io.run_for(5s);

  ASSERT_EQ(seen.size(), 5u);
  const std::vector<bool> expected{true, false, true, false, false};
  for (std::size_t i = 0; i < seen.size(); ++i) {
    EXPECT_EQ(seen[i].rising, expected[i]) << i;
    EXPECT_EQ(seen[i].timestamp, std::chrono::nanoseconds(i + 1)) << i;
  }
  EXPECT_FALSE(sense.level());
  EXPECT_LE(log.reads, 5);  // woken by the descriptor, not polling
}

TEST(PowerSense, WaitsWithoutBusyLooping) {
  boost::asio::io_context io;
  PipeLog log;
  int edges = 0;
  PowerSense sense(io, std::make_unique<PipeEdgeSource>(log), [&](const GpioEdge&) { ++edges; });
  io.run_for(50ms);
  EXPECT_EQ(edges, 0);
  EXPECT_EQ(log.reads, 0);
}

TEST(PowerSense, DestructionCancelsAndLeavesTheDescriptorToTheSource) {
  boost::asio::io_context io;
  PipeLog log;
  int edges = 0;
  auto sense = std::make_unique<PowerSense>(io, std::make_unique<PipeEdgeSource>(log),
                                            [&](const GpioEdge&) { ++edges; });
  io.run_for(10ms);
  sense.reset();
  // The source closed its own descriptor after PowerSense released it: nothing closed it first.
  EXPECT_EQ(log.close_result, 0) << "errno " << log.close_errno;

  // The cancelled wait completes without calling the handler, and no work is left.
  const auto start = std::chrono::steady_clock::now();
  io.restart();
  io.run_for(5s);
  EXPECT_LT(std::chrono::steady_clock::now() - start, 1s);
  EXPECT_EQ(edges, 0);
}

TEST(PowerSense, DestructionFromTheHandlerStopsDelivery) {
  boost::asio::io_context io;
  PipeLog log;
  int edges = 0;
  std::unique_ptr<PowerSense> sense;
  sense =
      std::make_unique<PowerSense>(io, std::make_unique<PipeEdgeSource>(log), [&](const GpioEdge&) {
        ++edges;
        sense.reset();
      });
  send(log, "rfr");
  io.run_for(5s);
  EXPECT_EQ(edges, 1);
  EXPECT_EQ(log.close_result, 0);
}

TEST(PowerSense, ReadFailureGoesToTheErrorHandlerAndStopsWaiting) {
  boost::asio::io_context io;
  PipeLog log;
  std::vector<GpioEdge> seen;
  std::vector<std::string> errors;
  PowerSense sense(
      io, std::make_unique<PipeEdgeSource>(log),
      [&](const GpioEdge& edge) { seen.push_back(edge); },
      [&](const std::string& error) { errors.push_back(error); });
  send(log, "x");
  io.run_for(5s);  // returns once the sense has stopped waiting: no work left
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("fake pipe line"), std::string::npos) << errors[0];
  EXPECT_NE(errors[0].find("read failed"), std::string::npos) << errors[0];
  EXPECT_TRUE(seen.empty());
}

TEST(PowerSense, RejectsMissingParts) {
  boost::asio::io_context io;
  PipeLog log;
  EXPECT_THROW(PowerSense(io, nullptr, [](const GpioEdge&) {}), core::InvalidInput);
  EXPECT_THROW(PowerSense(io, std::make_unique<PipeEdgeSource>(log), {}), core::InvalidInput);
}

}  // namespace
}  // namespace tofcomp::hal
