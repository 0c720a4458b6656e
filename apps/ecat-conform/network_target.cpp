#include <fmt/format.h>

#include <thread>

#include "apps/ecat-conform/target.hpp"
#include "transport/raw_socket_transport.hpp"
#include "transport/udp_transport.hpp"

namespace ecat::conform {

namespace {

template <typename T>
class WireTarget final : public Target {
 public:
  WireTarget(T transport, std::string description)
      : transport_(std::move(transport)), description_(std::move(description)) {}
  transport::Transport& transport() override { return transport_; }
  const Clock& clock() const override { return clock_; }
  // The program's edge: sleeping is fine here, never inside the stack.
  void wait(Nanoseconds d) override { std::this_thread::sleep_for(d); }
  std::string description() const override { return description_; }

 private:
  T transport_;
  SteadyClock clock_;
  std::string description_;
};

}  // namespace

Expected<std::unique_ptr<Target>, std::string> make_raw_socket_target(const std::string& interface_name) {
  auto t = transport::RawSocketTransport::open(interface_name);
  if (!t) return fail(fmt::format("{}: {}", interface_name, transport::describe(t.error())));
  if (auto d = transport::drop_privileges(); !d) return fail(std::string("cannot drop privileges"));
  return std::unique_ptr<Target>(
      std::make_unique<WireTarget<transport::RawSocketTransport>>(std::move(*t), "raw socket " + interface_name));
}

Expected<std::unique_ptr<Target>, std::string> make_udp_target(const std::string& address) {
  auto ep = transport::parse_udp_endpoint(address);
  if (!ep) return fail(fmt::format("{}: expected ADDR:PORT", address));
  auto t = transport::UdpTransport::connect(*ep);
  if (!t) return fail(fmt::format("{}: {}", address, transport::describe(t.error())));
  return std::unique_ptr<Target>(
      std::make_unique<WireTarget<transport::UdpTransport>>(std::move(*t), "udp " + address));
}

}  // namespace ecat::conform
