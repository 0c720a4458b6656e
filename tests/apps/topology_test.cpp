// The --topology file of ecat-slave (docs/topology.md): slaves, their
// cables by port, the redundant master port, and errors with file:line.
#include <gtest/gtest.h>

#include "apps/ecat-slave/topology.hpp"

namespace ecat::app {
namespace {

constexpr const char* kTree = R"(# coupler -> junction -> two branches
slave coupler coupler-3port.xml
slave io      generic-servo.xml at coupler:1
slave junction junction-4port.xml at io:1
slave a1 generic-servo.xml at junction:3
slave a2 /abs/generic-servo.xml at a1:1   # absolute path kept
slave b  generic-servo.xml at junction:2 port 0
redundant a2:1
)";

TEST(Topology, ParsesSlavesPortsAndRedundantPort) {
  auto t = parse_topology(kTree, "tree.txt", "/base");
  ASSERT_TRUE(t) << t.error();
  ASSERT_EQ(t->slaves.size(), 6u);
  EXPECT_EQ(t->slaves[0].name, "coupler");
  EXPECT_EQ(t->slaves[0].device_file, "/base/coupler-3port.xml");
  EXPECT_FALSE(t->slaves[0].parent.has_value());
  EXPECT_EQ(t->slaves[3].parent, 2u);
  EXPECT_EQ(t->slaves[3].parent_port, 3u);
  EXPECT_EQ(t->slaves[3].port, 0u);
  EXPECT_EQ(t->slaves[4].device_file, "/abs/generic-servo.xml");
  EXPECT_EQ(t->slaves[5].parent, 2u);
  EXPECT_EQ(t->slaves[5].parent_port, 2u);
  EXPECT_EQ(t->slaves[5].line, 7);
  ASSERT_TRUE(t->redundant.has_value());
  EXPECT_EQ(t->redundant->slave, 4u);
  EXPECT_EQ(t->redundant->port, 1u);
  auto p = t->parse_port("junction:3");
  ASSERT_TRUE(p);
  EXPECT_EQ(p->slave, 2u);
  EXPECT_EQ(p->port, 3u);
}

TEST(Topology, CableAndInnerDelays) {
  auto t = parse_topology("slave c c.xml inner 260 140\n"
                          "slave j j.xml at c:1 cable 150 inner 220 100\n"
                          "slave b b.xml at j:2 port 1 cable 930\n",
                          "d.txt", "");
  ASSERT_TRUE(t) << t.error();
  ASSERT_EQ(t->slaves.size(), 3u);
  EXPECT_FALSE(t->slaves[0].cable.has_value());
  EXPECT_EQ(t->slaves[0].processing, Nanoseconds{260});
  EXPECT_EQ(t->slaves[0].forwarding, Nanoseconds{140});
  EXPECT_EQ(t->slaves[1].cable, Nanoseconds{150});
  EXPECT_EQ(t->slaves[1].processing, Nanoseconds{220});
  EXPECT_EQ(t->slaves[1].forwarding, Nanoseconds{100});
  EXPECT_EQ(t->slaves[2].parent_port, 2u);
  EXPECT_EQ(t->slaves[2].port, 1u);
  EXPECT_EQ(t->slaves[2].cable, Nanoseconds{930});
  EXPECT_FALSE(t->slaves[2].processing.has_value());
}

TEST(Topology, ErrorsNameFileAndLine) {
  auto error_of = [](const char* text) {
    auto t = parse_topology(text, "t.txt", "");
    return t ? std::string("no error") : t.error();
  };
  EXPECT_EQ(error_of("slave a x.xml\nslave b x.xml\n"),
            "t.txt:2: slave 'b' needs 'at PARENT:PORT' (only the first slave sits on the master)");
  EXPECT_EQ(error_of("slave a x.xml\nslave b x.xml at c:1\n"), "t.txt:2: 'c:1': no slave named 'c'");
  EXPECT_EQ(error_of("slave a x.xml\nslave b x.xml at a:4\n"), "t.txt:2: 'a:4': port must be 0..3");
  EXPECT_EQ(error_of("slave a x.xml\nslave b x.xml at a:1\nslave c x.xml at a:1\n"),
            "t.txt:3: port 1 of 'a' is already cabled");
  EXPECT_EQ(error_of("slave a x.xml\nslave b x.xml at a:0\n"), "t.txt:2: port 0 of 'a' is already cabled");
  EXPECT_EQ(error_of("slave a x.xml\nslave a x.xml at a:1\n"), "t.txt:2: slave 'a' defined twice");
  EXPECT_EQ(error_of("slave a x.xml\nlink a:1\n"), "t.txt:2: unknown statement 'link' (slave, redundant)");
  EXPECT_EQ(error_of("slave a x.xml at\n"),
            "t.txt:1: expected: slave NAME FILE [at PARENT:PORT [port N]] [cable NS] [inner P F]");
  EXPECT_EQ(error_of("slave a x.xml\nslave b x.xml at a:1 cable\n"),
            "t.txt:2: expected: slave NAME FILE [at PARENT:PORT [port N]] [cable NS] [inner P F]");
  EXPECT_EQ(error_of("slave a x.xml\nslave b x.xml at a:1 cable 1us\n"),
            "t.txt:2: '1us': expected a time in ns (0..1000000)");
  EXPECT_EQ(error_of("slave a x.xml\nslave b x.xml at a:1 inner 5 2000000\n"),
            "t.txt:2: '2000000': expected a time in ns (0..1000000)");
  EXPECT_EQ(error_of("slave a x.xml cable 100\n"), "t.txt:1: 'cable' needs 'at PARENT:PORT' (the master's cable takes 0)");
  EXPECT_EQ(error_of("slave a x.xml\nslave b x.xml at a:1 speed 3\n"),
            "t.txt:2: expected 'at', 'cable' or 'inner', found 'speed'");
  EXPECT_EQ(error_of("# nothing\n"), "t.txt: no slave");
  EXPECT_EQ(error_of("slave a x.xml\nredundant a:1\nredundant a:2\n"), "t.txt:3: the master has one redundant port");
}

}  // namespace
}  // namespace ecat::app
