// A PDI host on its Unix socket over one emulated slave with no built-in
// firmware, on simulated time, and a firmware's side of the socket as raw
// bytes: the bench of tests/pdi_host/pdi_host_*_test.cpp.
#pragma once

#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/time.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "pdi_host/pdi_host.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {

using Bytes8 = std::vector<std::uint8_t>;

struct HostBench {
  explicit HostBench(pdi_host::PdiChip chip = pdi_host::PdiChip::Direct) {
    char templ[] = "/tmp/pdi_host_test.XXXXXX";
    dir = ::mkdtemp(templ);
    path = dir + "/pdi.sock";
    auto d = esi::load_default_device();
    if (!d) throw std::runtime_error("default device");
    slave::SlaveOptions o;
    o.external_firmware = true;
    p.add(*d, o);
    auto h = pdi_host::PdiHost::open(path, p.chain[0].esc(), chip, p.clock,
                                     [this](const std::string& line) { log.push_back(line); });
    if (!h) throw std::runtime_error(h.error());
    host = std::move(*h);
  }
  ~HostBench() {
    host.reset();
    ::rmdir(dir.c_str());
  }
  int connect_firmware() {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::snprintf(a.sun_path, sizeof(a.sun_path), "%s", path.c_str());
    EXPECT_EQ(::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof(a)), 0);
    timeval tv{1, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
    return fd;
  }
  // Reads exactly n bytes (the host has been serviced before).
  static Bytes8 take(int fd, std::size_t n) {
    Bytes8 b(n);
    std::size_t got = 0;
    while (got < n) {
      const ssize_t r = ::recv(fd, b.data() + got, n - got, 0);
      if (r <= 0) break;
      got += static_cast<std::size_t>(r);
    }
    b.resize(got);
    return b;
  }
  static void send(int fd, const Bytes8& b) { ASSERT_EQ(::send(fd, b.data(), b.size(), 0), static_cast<ssize_t>(b.size())); }

  std::string dir;
  std::string path;
  InProcess p;
  std::vector<std::string> log;
  std::unique_ptr<pdi_host::PdiHost> host;
};

constexpr std::size_t kGreeting = 8 + 24;  // HELLO + the lines

}  // namespace ecat::test
