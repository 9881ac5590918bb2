// A client connection's read, write and idle coroutines.
#include "daemon/socket/client_connection.hpp"

#include <array>
#include <utility>
#include <vector>

namespace tofcomp::daemon::socket {

namespace asio = boost::asio;
using asio::awaitable;
using asio::use_awaitable;
using Clock = std::chrono::steady_clock;

namespace {
constexpr std::size_t kReadChunk = 4096;
constexpr std::size_t kLinesPerWrite = 32;  // queued lines gathered into one write
}  // namespace

ClientConnection::ClientConnection(Stream stream, std::uint64_t number, Limits limits, Owner& owner)
    : stream_(std::move(stream)),
      number_(number),
      limits_(limits),
      owner_(owner),
      peer_(peer_credentials(stream_.native_handle())),
      timer_(stream_.get_executor()),
      resume_timer_(stream_.get_executor()),
      idle_timer_(stream_.get_executor()),
      last_activity_(Clock::now()) {}

void ClientConnection::start() {
  asio::co_spawn(stream_.get_executor(), read_loop(shared_from_this()), asio::detached);
  asio::co_spawn(stream_.get_executor(), write_loop(shared_from_this()), asio::detached);
  if (limits_.idle_timeout.count() > 0) {
    asio::co_spawn(stream_.get_executor(), idle_watch(shared_from_this()), asio::detached);
  }
}

bool ClientConnection::fits(std::size_t bytes, std::size_t bound) const {
  return queued_bytes_ == 0 || (bytes <= bound && queued_bytes_ <= bound - bytes);
}

void ClientConnection::push(std::shared_ptr<const std::string> line) {
  if (!accepting()) return;
  queued_bytes_ += line->size();
  queue_.push_back(std::move(line));
  timer_.cancel();
}

void ClientConnection::close_after_flush() {
  if (!accepting()) return;
  draining_ = true;
  received_.clear();
  timer_.cancel();
  resume_timer_.cancel();
}

void ClientConnection::close(const std::string& why, bool notify_owner) {
  if (closed_) return;
  closed_ = true;
  boost::system::error_code ignored;
  stream_.close(ignored);
  timer_.cancel();
  resume_timer_.cancel();
  idle_timer_.cancel();
  const std::size_t unwritten = queued_bytes_;
  queue_.clear();
  queued_bytes_ = 0;
  received_.clear();
  if (notify_owner) owner_.on_closed(*this, why, unwritten);
}

void ClientConnection::end_of_input() {
  input_ended_ = true;
  if (draining_) {
    // The client has read our end or stopped sending: the linger has nothing left to wait for.
    timer_.cancel();
    return;
  }
  // A client that sent its requests and shut its side (shutdown(SHUT_WR), `nc -N`) is answered
  // all of them, a last line without '\n' included, and their replies are written, not dropped
  // (the owner then ends the connection, or streams on to a subscriber).
  if (!received_.empty() && received_.back() != '\n') received_.push_back('\n');
  answer_received();
}

void ClientConnection::answer_received() {
  std::size_t start = 0;
  while (accepting() && !paused()) {
    const std::size_t newline = received_.find('\n', start);
    if (newline == std::string::npos) break;
    std::string_view line(received_.data() + start, newline - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    start = newline + 1;
    if (!line.empty()) {
      last_activity_ = Clock::now();
      owner_.on_line(*this, line);
    }
  }
  if (!accepting()) return;  // on_line dropped the connection or ended it
  received_.erase(0, start);
  if (input_ended_) {
    // Nothing more will come: once every received line is answered, the owner decides.
    if (received_.empty() && !input_end_told_) {
      input_end_told_ = true;
      owner_.on_input_ended(*this);
    }
    return;
  }
  // Only a partial line is left when nothing waits: it must stay within the limit.
  if (!paused() && received_.size() > limits_.max_line_bytes) owner_.on_overlong(*this);
}

awaitable<void> ClientConnection::read_loop(
    std::shared_ptr<ClientConnection> /*keeps this alive*/) {
  std::array<char, kReadChunk> chunk;
  for (;;) {
    boost::system::error_code ec;
    if (accepting() && paused()) {
      // Back-pressure: the socket is not read until the replies queued are written.
      resume_timer_.expires_at(Clock::time_point::max());
      co_await resume_timer_.async_wait(asio::redirect_error(use_awaitable, ec));
      if (closed_) co_return;
      continue;
    }
    const std::size_t n = co_await stream_.async_read_some(asio::buffer(chunk),
                                                           asio::redirect_error(use_awaitable, ec));
    if (closed_) co_return;
    if (ec == asio::error::eof) {
      end_of_input();
      co_return;
    }
    if (ec) {
      close("read failed: " + ec.message());
      co_return;
    }
    if (draining_) continue;  // lingering: what the client still sends is discarded
    received_.append(chunk.data(), n);
    answer_received();
  }
}

awaitable<void> ClientConnection::write_loop(
    std::shared_ptr<ClientConnection> /*keeps this alive*/) {
  std::vector<std::shared_ptr<const std::string>> batch;
  std::vector<asio::const_buffer> buffers;
  for (;;) {
    boost::system::error_code ec;
    if (closed_) co_return;
    if (queue_.empty()) {
      if (draining_) {
        // Everything is written: end our side, give the client time to read it and close.
        stream_.shutdown(Stream::shutdown_send, ec);
        if (!input_ended_) {
          timer_.expires_after(kLingerAfterLastLine);
          co_await timer_.async_wait(asio::redirect_error(use_awaitable, ec));
        }
        if (closed_) co_return;
        close("closed after its last reply");
        co_return;
      }
      timer_.expires_at(asio::steady_timer::time_point::max());
      co_await timer_.async_wait(asio::redirect_error(use_awaitable, ec));
      continue;
    }
    batch.clear();
    buffers.clear();
    std::size_t bytes = 0;
    for (std::size_t i = 0; i < queue_.size() && i < kLinesPerWrite; ++i) {
      batch.push_back(queue_[i]);
      buffers.push_back(asio::buffer(*queue_[i]));
      bytes += queue_[i]->size();
    }
    co_await asio::async_write(stream_, buffers, asio::redirect_error(use_awaitable, ec));
    if (closed_) co_return;
    if (ec) {
      close("write failed: " + ec.message());
      co_return;
    }
    const bool was_paused = paused();
    queue_.erase(queue_.begin(), queue_.begin() + static_cast<std::ptrdiff_t>(batch.size()));
    queued_bytes_ -= bytes;
    last_activity_ = Clock::now();  // something was delivered: the connection is in use
    owner_.on_written(*this, bytes);
    if (was_paused && !paused() && accepting()) {
      // The requests that waited are answered now; the reader reads again.
      answer_received();
      resume_timer_.cancel();
    }
  }
}

awaitable<void> ClientConnection::idle_watch(
    std::shared_ptr<ClientConnection> /*keeps this alive*/) {
  for (;;) {
    boost::system::error_code ec;
    idle_timer_.expires_at(last_activity_ + limits_.idle_timeout);
    co_await idle_timer_.async_wait(asio::redirect_error(use_awaitable, ec));
    if (!accepting()) co_return;
    // A line came or a line was delivered meanwhile.
    if (Clock::now() < last_activity_ + limits_.idle_timeout) continue;
    last_activity_ = Clock::now();
    owner_.on_idle(*this);
  }
}

}  // namespace tofcomp::daemon::socket
