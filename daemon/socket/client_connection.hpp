// One client of the socket server: its request lines read and framed, its outgoing lines in a
// queue written asynchronously (gathered, in order), and its closing: at once, or after the
// queue is written (half-close, then a short linger that discards what the client still sends,
// so that it reads the last line and then the end of the stream, not a reset).
// Back-pressure: while more than pause_bytes are queued for it, the connection answers none of
// the requests it has received and reads no more from the socket; it goes on once the queue is
// written down to pause_bytes, so a client that pipelines requests gets every reply in order.
// Idle: a connection that sends no line and is delivered no line for idle_timeout is reported
// to the owner.
// Lives on the server's io_context thread; the coroutines keep it alive until they end.
#pragma once

#include <boost/asio.hpp>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "daemon/socket/peer_credentials.hpp"

namespace tofcomp::daemon::socket {

inline constexpr std::chrono::milliseconds kLingerAfterLastLine{2000};

class ClientConnection : public std::enable_shared_from_this<ClientConnection> {
 public:
  using Stream = boost::asio::local::stream_protocol::socket;

  // Told what happens to the connection; never called once the connection is closed.
  class Owner {
   public:
    // A complete line (without '\n' and a '\r' before it), not empty.
    virtual void on_line(ClientConnection& connection, std::string_view line) = 0;
    // More than max_line_bytes arrived without a '\n'.
    virtual void on_overlong(ClientConnection& connection) = 0;
    // bytes of queued lines were written.
    virtual void on_written(ClientConnection& connection, std::size_t bytes) = 0;
    // No line arrived and none was written for the idle timeout (told again after each further
    // timeout).
    virtual void on_idle(ClientConnection& connection) = 0;
    // The client shut its side and every request it sent is answered (once). The owner ends
    // the connection after its replies (close_after_flush) or, for a subscriber, lets it go on
    // receiving until it closes.
    virtual void on_input_ended(ClientConnection& connection) = 0;
    // The connection closed (once); unwritten_bytes were still queued.
    virtual void on_closed(ClientConnection& connection, const std::string& why,
                           std::size_t unwritten_bytes) = 0;

   protected:
    virtual ~Owner() = default;
  };

  struct Limits {
    std::size_t max_line_bytes = 0;
    std::size_t pause_bytes = 0;  // queued beyond this, requests wait
    std::chrono::milliseconds idle_timeout{0};
  };

  ClientConnection(Stream stream, std::uint64_t number, Limits limits, Owner& owner);

  // Starts reading and writing.
  void start();

  // True when a line of bytes may be queued under bound: the queue is empty (one line always
  // goes) or the queued bytes plus these stay within bound.
  bool fits(std::size_t bytes, std::size_t bound) const;
  // Queues a line; ignored once the connection is closing.
  void push(std::shared_ptr<const std::string> line);
  // Reads no more requests; closes once the queue is written.
  void close_after_flush();
  // Closes now; tells the owner (unless notify_owner is false) why.
  void close(const std::string& why, bool notify_owner = true);

  bool accepting() const { return !closed_ && !draining_; }
  bool closed() const { return closed_; }
  std::size_t queued_bytes() const { return queued_bytes_; }
  std::uint64_t number() const { return number_; }
  // The peer as it connected (SO_PEERCRED); nullopt if the kernel gave none.
  const std::optional<PeerCredentials>& peer() const { return peer_; }

 private:
  Stream stream_;
  std::uint64_t number_;
  Limits limits_;
  Owner& owner_;
  std::optional<PeerCredentials> peer_;
  boost::asio::steady_timer timer_;         // wakes the writer; then times the linger
  boost::asio::steady_timer resume_timer_;  // wakes the reader when requests may go on
  boost::asio::steady_timer idle_timer_;
  std::chrono::steady_clock::time_point last_activity_;  // the last line read or written
  std::deque<std::shared_ptr<const std::string>> queue_;
  std::size_t queued_bytes_ = 0;
  std::string received_;  // bytes read and not yet answered: whole lines, then a partial one
  bool draining_ = false;
  bool input_ended_ = false;  // the client shut its side: no more requests will come
  bool input_end_told_ = false;  // the owner was told (on_input_ended)
  bool closed_ = false;

  boost::asio::awaitable<void> read_loop(std::shared_ptr<ClientConnection> self);
  boost::asio::awaitable<void> write_loop(std::shared_ptr<ClientConnection> self);
  boost::asio::awaitable<void> idle_watch(std::shared_ptr<ClientConnection> self);
  // Back-pressure: requests wait while more than pause_bytes are queued.
  bool paused() const { return queued_bytes_ > limits_.pause_bytes; }
  // Answers the whole lines received, in order, while not paused; once the input has ended
  // and every line is answered, tells the owner.
  void answer_received();
  // The client shut its side: what it sent is answered, and its replies written, before the
  // connection may end.
  void end_of_input();
};

}  // namespace tofcomp::daemon::socket
