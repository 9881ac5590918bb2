// A reader checks a ring's header before it trusts it: a wrong magic, layout version, byte
// order, slot size or object size is an error that names the shm object and the mismatch. A
// writer does not remove an object of its name that is not a tofcomp ring.
#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"
#include "ipc/ring/ring_reader.hpp"
#include "ipc/ring/ring_writer.hpp"
#include "tests/ipc/ring/ring_test_support.hpp"

namespace tofcomp::ipc::ring {
namespace {

using testing::RawShm;
using testing::ScopedRingName;

// The message of the core::Error that opening a reader of `name` raises ("" if none).
std::string open_error(const std::string& name) {
  try {
    RingReader reader(name);
  } catch (const core::Error& e) {
    return e.what();
  }
  return "";
}

void expect_contains(const std::string& message, const std::string& part) {
  EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
}

TEST(RingHeaderValidation, WrongMagicIsNamed) {
  const ScopedRingName name("magic");
  RingWriter writer(name, 2, 4);
  RawShm raw(name);
  raw.put<char>(3, 'X');  // "TOFXRING"
  const std::string message = open_error(name);
  expect_contains(message, "shm object '" + name.str() + "'");
  expect_contains(message, "magic is 0x474e495258464f54");
  expect_contains(message, "not a tofcomp ring");
}

TEST(RingHeaderValidation, WrongLayoutVersionIsNamed) {
  const ScopedRingName name("version");
  RingWriter writer(name, 2, 4);
  RawShm raw(name);
  raw.put<std::uint32_t>(8, 1);  // a ring of the first layout, without the rays' timing
  const std::string message = open_error(name);
  expect_contains(message, "shm object '" + name.str() + "'");
  expect_contains(message, "layout version is 1, this reader reads version 2");
}

TEST(RingHeaderValidation, WrongByteOrderIsNamed) {
  const ScopedRingName name("endian");
  RingWriter writer(name, 2, 4);
  RawShm raw(name);
  raw.put<std::uint32_t>(12, 0x04030201u);
  expect_contains(open_error(name), "another byte order");
}

TEST(RingHeaderValidation, InconsistentSizesAreNamed) {
  const ScopedRingName name("sizes");
  RingWriter writer(name, 2, 4);
  RawShm raw(name);
  // 4 beams: 112 + 4 * 56 = 336, rounded to 384.
  raw.put<std::uint32_t>(20, 385);
  expect_contains(open_error(name), "slot_size (for max_beams 4) is 385, expected 384");
  raw.put<std::uint32_t>(20, 384);
  raw.put<std::uint32_t>(24, 3);  // three slots do not fit in an object sized for two
  expect_contains(open_error(name), "describes 1280 bytes (3 slots of 384)");
  raw.put<std::uint32_t>(24, 2);
  raw.put<std::uint32_t>(40, 64);
  expect_contains(open_error(name), "beam_record_size is 64, expected 56");
  raw.put<std::uint32_t>(40, 56);
  raw.put<std::uint32_t>(32, 8);
  expect_contains(open_error(name), "max_modes is 8, expected 4");
  raw.put<std::uint32_t>(32, 4);
  EXPECT_EQ(open_error(name), "");  // restored: a valid ring again
}

TEST(RingHeaderValidation, ObjectThatIsNotARingIsRefusedAndLeftInPlace) {
  const ScopedRingName name("foreign");
  testing::create_raw_object(name, 4096, "NOTARING and some data of another program");
  expect_contains(open_error(name), "not a tofcomp ring");
  try {
    RingWriter writer(name, 2, 4);
    FAIL() << "the writer replaced an object that is not a ring";
  } catch (const core::Error& e) {
    expect_contains(e.what(), "shm object '" + name.str() + "' exists and is not a tofcomp ring");
  }
  const RawShm raw(name);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(raw.bytes()), 8), "NOTARING");
}

TEST(RingHeaderValidation, EmptyObjectIsReportedAsNotYetCreated) {
  const ScopedRingName name("empty");
  testing::create_raw_object(name, 0, "");
  expect_contains(open_error(name), "is 0 bytes, smaller than the 128-byte ring header");
  // A writer takes an empty object for the remains of a failed creation and replaces it.
  RingWriter writer(name, 2, 4);
  EXPECT_EQ(open_error(name), "");
}

}  // namespace
}  // namespace tofcomp::ipc::ring
