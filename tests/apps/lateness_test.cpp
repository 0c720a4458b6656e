// ecat-master's lateness histogram (apps/ecat-master/lateness.hpp): bucket
// edges are lower-inclusive, the last bucket takes everything from 20 ms on.
#include <gtest/gtest.h>

#include "apps/ecat-master/lateness.hpp"

namespace ecat::app {
namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;

TEST(LatenessHistogram, EdgesAndText) {
  LatenessHistogram h;
  h.add(Nanoseconds{0});
  h.add(Nanoseconds{9'999});
  h.add(microseconds(10));     // first edge: second bucket
  h.add(microseconds(999));
  h.add(milliseconds(1));
  h.add(milliseconds(20));     // last edge: last bucket
  h.add(milliseconds(97));
  EXPECT_EQ(h.count(0), 2u);
  EXPECT_EQ(h.count(1), 1u);
  EXPECT_EQ(h.count(5), 1u);
  EXPECT_EQ(h.count(6), 1u);
  EXPECT_EQ(h.count(9), 2u);
  EXPECT_EQ(h.max(), milliseconds(97));
  EXPECT_EQ(h.to_string(), "<10:2 <50:1 <100:0 <250:0 <500:0 <1000:1 <2000:1 <5000:0 <20000:0 >=20000:2");
}

}  // namespace
}  // namespace ecat::app
