// Ring: the ring reader of ipc/ring, its batches handed out one scan at a time.
#include <deque>
#include <utility>

#include "client/public_scan.hpp"
#include "core/error.hpp"
#include "ipc/ring/ring_reader.hpp"
#include "tofcomp/client.hpp"

namespace tofcomp::client {

using client_detail::public_scan;

namespace {

// Scans copied out of the ring at one read: enough to drain a full ring of the default size in
// a few reads, few enough that a slow caller does not hold many copies.
constexpr std::size_t kRingBatch = 16;

template <typename F>
auto ring_guarded(F&& f) {
  try {
    return f();
  } catch (const core::Error& e) {
    throw Error(ErrorKind::Ring, e.what());
  }
}

Scan whole(const ipc::CompensatedScan& scan) {
  return public_scan(scan, {0, scan.beams.size()});
}

}  // namespace

struct Ring::Impl {
  ipc::ring::RingReader reader;
  std::deque<ipc::CompensatedScan> pending;
  explicit Impl(const std::string& name) : reader(name) {}
};

Ring::Ring(const std::string& name)
    : impl_(ring_guarded([&] { return std::make_unique<Impl>(name); })) {}
Ring::~Ring() = default;
Ring::Ring(Ring&&) noexcept = default;
Ring& Ring::operator=(Ring&&) noexcept = default;

std::optional<Scan> Ring::latest() {
  return ring_guarded([&]() -> std::optional<Scan> {
    const auto scan = impl_->reader.latest();
    if (!scan) return std::nullopt;
    return whole(*scan);
  });
}

std::optional<Scan> Ring::next() {
  return ring_guarded([&]() -> std::optional<Scan> {
    if (impl_->pending.empty()) {
      auto batch = impl_->reader.read_new(kRingBatch);
      for (auto& scan : batch.scans) impl_->pending.push_back(std::move(scan));
    }
    if (impl_->pending.empty()) return std::nullopt;
    Scan scan = whole(impl_->pending.front());
    impl_->pending.pop_front();
    return scan;
  });
}

std::uint64_t Ring::lost() const {
  return impl_->reader.counters().lost;
}

const std::string& Ring::name() const {
  return impl_->reader.name();
}

}  // namespace tofcomp::client
