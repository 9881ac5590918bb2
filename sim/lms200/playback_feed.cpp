#include "sim/lms200/playback_feed.hpp"

#include <cmath>
#include <utility>

#include "core/error.hpp"

namespace tofcomp::sim::lms200 {

using Clock = std::chrono::steady_clock;

PlaybackFeed::PlaybackFeed(Handlers handlers) : handlers_(std::move(handlers)) {
  if (!handlers_.case_reading || !handlers_.power) {
    throw core::InvalidInput("playback feed: a handler for case readings and power is required");
  }
}

void PlaybackFeed::event_played(const PlaybackEvent& event) {
  std::lock_guard lock(mutex_);
  if (event.scan_ranges_mm.empty()) {
    queue_.emplace_back(event);
  } else {
    queue_.emplace_back(SentRanges{event.time_s, event.scan_ranges_mm, Clock::now()});
  }
}

bool PlaybackFeed::same_ranges(const SentRanges& sent, std::span<const double> ranges_mm,
                               std::span<const std::uint8_t> no_echo) {
  if (sent.ranges_mm.size() != ranges_mm.size()) return false;
  for (std::size_t b = 0; b < ranges_mm.size(); ++b) {
    const bool none = std::isnan(sent.ranges_mm[b]);
    if (none != (no_echo[b] != 0)) return false;
    if (!none && sent.ranges_mm[b] != ranges_mm[b]) return false;
  }
  return true;
}

void PlaybackFeed::hand_over(const PlaybackEvent& event) const {
  if (event.power) handlers_.power(event.time_s, *event.power);
  if (event.case_c) handlers_.case_reading(event.time_s, *event.case_c);
}

std::optional<double> PlaybackFeed::scan_arrived(std::span<const double> ranges_mm,
                                                 std::span<const std::uint8_t> no_echo) {
  std::vector<PlaybackEvent> before;
  std::optional<double> time_s;
  {
    std::lock_guard lock(mutex_);
    std::size_t match = 0;
    while (match < queue_.size()) {
      const auto* sent = std::get_if<SentRanges>(&queue_[match]);
      if (sent && same_ranges(*sent, ranges_mm, no_echo)) break;
      ++match;
    }
    if (match == queue_.size()) return std::nullopt;
    time_s = std::get<SentRanges>(queue_[match]).time_s;
    for (std::size_t i = 0; i < match; ++i) {
      if (const auto* event = std::get_if<PlaybackEvent>(&queue_[i])) {
        before.push_back(*event);
      }
    }
    queue_.erase(queue_.begin(), queue_.begin() + static_cast<std::ptrdiff_t>(match) + 1);
  }
  for (const auto& event : before) hand_over(event);
  return time_s;
}

void PlaybackFeed::deliver(Clock::duration lost_after) {
  const auto now = Clock::now();
  std::vector<PlaybackEvent> ready;
  {
    std::lock_guard lock(mutex_);
    while (!queue_.empty()) {
      if (const auto* event = std::get_if<PlaybackEvent>(&queue_.front())) {
        ready.push_back(*event);
      } else if (now - std::get<SentRanges>(queue_.front()).sent_at < lost_after) {
        break;  // on its way: the events after it wait for it
      }
      queue_.pop_front();
    }
  }
  for (const auto& event : ready) hand_over(event);
}

}  // namespace tofcomp::sim::lms200
