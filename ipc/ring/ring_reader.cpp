// A reader of tofcompd's shared-memory ring: see ring_reader.hpp.
#include "ipc/ring/ring_reader.hpp"

#include <unistd.h>

#include <algorithm>
#include <utility>

#include "core/error.hpp"
#include "ipc/ring/ring_header.hpp"
#include "ipc/ring/seqlock_slot.hpp"
#include "ipc/user_name.hpp"

namespace tofcomp::ipc::ring {

namespace {

// latest() gives up after this many copies in a row lost to the writer: the writer would have
// to lap the whole ring during every one of them.
constexpr int kLatestAttempts = 1000;

std::vector<uid_t> accepted_owners(std::vector<uid_t> owners) {
  if (owners.empty()) {
    owners = {::geteuid(), 0};
    if (const auto daemon = user_named(kDaemonUser)) owners.push_back(*daemon);
  }
  std::sort(owners.begin(), owners.end());
  owners.erase(std::unique(owners.begin(), owners.end()), owners.end());
  return owners;
}

bool accepted(const std::vector<uid_t>& owners, uid_t uid) {
  return std::find(owners.begin(), owners.end(), uid) != owners.end();
}

std::string describe_users(const std::vector<uid_t>& owners) {
  std::string text;
  for (std::size_t i = 0; i < owners.size(); ++i) {
    if (i > 0) text += i + 1 == owners.size() ? " or " : ", ";
    text += describe_user(owners[i]);
  }
  return text;
}

// The ring to read for `name`: the object itself when an accepted user owns it; else the
// alternative tofcompd publishes to when its name is taken (shm_object.hpp), if an accepted user
// owns that. `name` becomes the object's name; `foreign` the owner of a refused one.
ShmMapping open_trusted_ring(std::string& name, const std::vector<uid_t>& owners,
                             std::optional<uid_t>& foreign) {
  validate_shm_name(name);
  const auto owner = object_owner(name);
  if (!owner) {
    throw core::Error(describe_object(name) + " does not exist (no /dev/shm" + name +
                      "): is its writer (tofcompd) running, with this ring name?");
  }
  if (accepted(owners, *owner)) {
    auto mapping = map_existing_read_only(name);
    if (!mapping) throw core::Error(describe_object(name) + " disappeared while it was opened");
    if (accepted(owners, mapping->owner())) return std::move(*mapping);
  }
  foreign = owner;
  std::string tried;
  for (const uid_t uid : owners) {
    const std::string alternative = alternative_ring_name(name, uid);
    tried += (tried.empty() ? "" : ", ") + alternative;
    if (object_owner(alternative) != uid) continue;
    if (auto mapping = map_existing_read_only(alternative); mapping && mapping->owner() == uid) {
      name = alternative;
      return std::move(*mapping);
    }
  }
  throw core::Error(describe_object(name) + " belongs to " + describe_user(*owner) + ", not to " +
                    describe_users(owners) +
                    ": tofcompd did not make it, and it is not read; nor is there a ring "
                    "where tofcompd publishes when its name is taken (" +
                    tried + "). Name the daemon's user with --owner if it is another");
}

}  // namespace

RingReader::RingReader(std::string name, RingReaderOptions options)
    : owners_(accepted_owners(std::move(options.owners))),
      name_(std::move(name)),
      mapping_(open_trusted_ring(name_, owners_, foreign_owner_)) {
  geometry_ = validate_ring_header(mapping_, name_);
  generation_ = read_header(mapping_.data()).generation;
  last_published_seen_ = load_published(mapping_.data());
  cursor_ = last_published_seen_;
}

void RingReader::check_size() const {
  const std::uint64_t now = mapping_.current_size();
  if (now < geometry_.ring_size()) {
    throw core::Error(describe_object(name_) + " shrank to " + std::to_string(now) +
                      " bytes while it was read, fewer than the " +
                      std::to_string(geometry_.ring_size()) +
                      " its header describes: it was truncated, and is not read further");
  }
}

const std::byte* RingReader::slot(std::uint64_t publish_index) const {
  return mapping_.data() + geometry_.slot_offset(publish_index);
}

std::uint64_t RingReader::oldest_available(std::uint64_t published) const {
  return published > geometry_.slot_count ? published - geometry_.slot_count : 0;
}

void RingReader::throw_corrupt(std::uint64_t publish_index) const {
  throw core::Error(describe_object(name_) + ": slot of publish " + std::to_string(publish_index) +
                    " claims more than the ring's max_beams (" +
                    std::to_string(geometry_.max_beams) + ") beams: the ring is corrupt");
}

bool RingReader::follow_restart_if_idle(std::uint64_t published) {
  const bool idle = published == last_published_seen_;
  if (!idle && load_writer_state(mapping_.data()) != kWriterClosed) return false;
  const auto now = identify_object(name_);
  if (!now || *now == mapping_.id()) return false;
  auto fresh = map_existing_read_only(name_);
  if (!fresh || ring_being_created(*fresh)) return false;  // try again at the next read
  if (!accepted(owners_, fresh->owner())) return false;    // not tofcompd's: not followed
  const RingGeometry geometry = validate_ring_header(*fresh, name_);
  const std::uint64_t generation = read_header(fresh->data()).generation;
  if (generation == generation_) return false;
  mapping_ = std::move(*fresh);
  geometry_ = geometry;
  generation_ = generation;
  const std::uint64_t fresh_published = load_published(mapping_.data());
  cursor_ = oldest_available(fresh_published);
  last_published_seen_ = fresh_published;
  ++counters_.writer_restarts;
  return true;
}

std::optional<CompensatedScan> RingReader::latest() {
  check_size();
  follow_restart_if_idle(load_published(mapping_.data()));
  for (int attempt = 0; attempt < kLatestAttempts; ++attempt) {
    check_size();
    const std::uint64_t published = load_published(mapping_.data());
    last_published_seen_ = published;
    if (published == 0) return std::nullopt;
    const std::uint64_t newest = published - 1;
    switch (read_slot(slot(newest), newest, geometry_.max_beams, scratch_)) {
      case SlotRead::kComplete:
        return scratch_;
      case SlotRead::kTorn:
        ++counters_.torn_reads;
        break;
      case SlotRead::kCorrupt:
        throw_corrupt(newest);
      case SlotRead::kOverwritten:
      case SlotRead::kNotYetWritten:
        break;
    }
  }
  throw core::Error(describe_object(name_) + ": no consistent copy of the newest scan in " +
                    std::to_string(kLatestAttempts) +
                    " attempts: the writer laps the ring faster than a scan can be copied");
}

ReadBatch RingReader::read_new(std::size_t max_scans) {
  check_size();
  ReadBatch batch;
  std::uint64_t published = load_published(mapping_.data());
  if (follow_restart_if_idle(published)) {
    batch.writer_restarted = true;
    published = load_published(mapping_.data());
  }
  last_published_seen_ = published;
  cursor_ = std::min(cursor_, published);
  const auto skip_overwritten = [&](std::uint64_t now_published) {
    const std::uint64_t oldest = oldest_available(now_published);
    if (cursor_ < oldest) {
      batch.lost += oldest - cursor_;
      cursor_ = oldest;
    }
  };
  skip_overwritten(published);
  batch.scans.reserve(
      static_cast<std::size_t>(std::min<std::uint64_t>(published - cursor_, max_scans)));
  while (cursor_ < published && batch.scans.size() < max_scans) {
    // Copied straight into the batch; a failed copy is dropped again.
    check_size();
    CompensatedScan& copy = batch.scans.emplace_back();
    const SlotRead outcome = read_slot(slot(cursor_), cursor_, geometry_.max_beams, copy);
    if (outcome != SlotRead::kComplete) batch.scans.pop_back();
    switch (outcome) {
      case SlotRead::kComplete:
        ++cursor_;
        break;
      case SlotRead::kTorn:
        ++batch.torn_reads;
        [[fallthrough]];
      case SlotRead::kOverwritten:
        // The writer has lapped the cursor: this scan is gone, and maybe more after it.
        ++batch.lost;
        ++cursor_;
        skip_overwritten(load_published(mapping_.data()));
        break;
      case SlotRead::kNotYetWritten:
        // Cannot happen below `published` (released after the slot); end the batch if it does.
        published = cursor_;
        break;
      case SlotRead::kCorrupt:
        throw_corrupt(cursor_);
    }
  }
  counters_.scans_read += batch.scans.size();
  counters_.lost += batch.lost;
  counters_.torn_reads += batch.torn_reads;
  return batch;
}

void RingReader::rewind_to_oldest() {
  check_size();
  cursor_ = oldest_available(load_published(mapping_.data()));
}

RingInfo RingReader::info() const {
  check_size();
  const RingHeader h = read_header(mapping_.data());
  RingInfo info;
  info.name = name_;
  info.layout_version = h.layout_version;
  info.slot_count = h.slot_count;
  info.max_beams = h.max_beams;
  info.max_modes = h.max_modes;
  info.slot_size = h.slot_size;
  info.writer_pid = h.writer_pid;
  info.generation = h.generation;
  info.writer_closed = h.writer_state == kWriterClosed;
  info.published = h.published;
  return info;
}

bool RingReader::writer_running() const {
  check_size();
  return load_writer_state(mapping_.data()) != kWriterClosed &&
         writer_lock_held(mapping_.fd(), name_);
}

}  // namespace tofcomp::ipc::ring
