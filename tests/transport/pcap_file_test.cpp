#include "transport/pcap_file.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "transport/in_memory_transport.hpp"
#include "transport_test_util.hpp"

namespace ecat::transport {
namespace {

std::string temp_path(const char* name) {
  return std::string(ECAT_BINARY_DIR) + "/" + name;
}

TEST(PcapFile, WriteThenReadKeepsBytesAndNanosecondTimestamps) {
  const std::string path = temp_path("transport_roundtrip.pcap");
  const auto a = test::brd_frame(0x11);
  const auto b = test::brd_frame(0x22);
  {
    auto w = PcapWriter::create(path);
    ASSERT_TRUE(w.has_value());
    ASSERT_TRUE(w->write(a, Nanoseconds{1'700'000'000'123'456'789}).has_value());
    ASSERT_TRUE(w->write(b, Nanoseconds{1'700'000'001'000'000'001}).has_value());
    EXPECT_EQ(w->records(), 2u);
  }
  auto r = PcapReader::open(path);
  ASSERT_TRUE(r.has_value());
  auto first = r->next();
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(first->frame, a);
  EXPECT_EQ(first->timestamp.count(), 1'700'000'000'123'456'789);
  auto second = r->next();
  ASSERT_TRUE(second.has_value());
  EXPECT_EQ(second->frame, b);
  EXPECT_EQ(second->timestamp.count(), 1'700'000'001'000'000'001);
  auto end = r->next();
  ASSERT_FALSE(end.has_value());
  EXPECT_EQ(end.error(), TransportError::EndOfFile);
  std::remove(path.c_str());
}

TEST(PcapFile, MissingOrGarbageFileIsAnErrorNotACrash) {
  EXPECT_EQ(PcapReader::open(temp_path("does/not/exist.pcap")).error(), TransportError::OpenFailed);
  const std::string path = temp_path("transport_garbage.pcap");
  {
    std::ofstream f(path, std::ios::binary);
    f << "this is not a capture file at all";
  }
  EXPECT_FALSE(PcapReader::open(path).has_value());
  std::remove(path.c_str());
  EXPECT_EQ(PcapWriter::create(temp_path("no/such/dir/x.pcap")).error(), TransportError::OpenFailed);
}

TEST(PcapFile, RecordingTransportWritesBothDirections) {
  const std::string path = temp_path("transport_recording.pcap");
  ManualClock clock(Nanoseconds{5'000});
  InMemoryTransport mem([](Bytes f) { f[f.size() - 2] = 1; });  // WKC = 1
  {
    auto w = PcapWriter::create(path);
    ASSERT_TRUE(w.has_value());
    RecordingTransport rec(mem, *w, clock);
    const auto frame = test::brd_frame(7);
    ASSERT_TRUE(rec.send(frame).has_value());
    clock.advance(Nanoseconds{250});
    std::uint8_t buf[kMaxFrameSize];
    auto n = rec.receive(buf, Nanoseconds{0});
    ASSERT_TRUE(n.has_value());
  }
  auto r = PcapReader::open(path);
  ASSERT_TRUE(r.has_value());
  auto out = r->next();
  auto in = r->next();
  ASSERT_TRUE(out && in);
  EXPECT_EQ(out->timestamp.count(), 5'000);
  EXPECT_EQ(in->timestamp.count(), 5'250);
  EXPECT_EQ(out->frame.back(), 0);
  EXPECT_EQ(in->frame[in->frame.size() - 2], 1);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace ecat::transport
