// Shared set-up for the ESM unit tests over the fake PDI: a device with a
// 128-byte mailbox at 0x1000/0x1080 and process data SMs at 0x1100/0x1180.
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "esc/esm.hpp"
#include "esm_fake_pdi.hpp"

namespace ecat::esc::test {

inline constexpr std::uint16_t kMbxOutStart = 0x1000;
inline constexpr std::uint16_t kMbxInStart = 0x1080;
inline constexpr std::uint16_t kMbxLength = 128;
inline constexpr std::uint8_t kMbxOutControl = 0x26;
inline constexpr std::uint8_t kMbxInControl = 0x22;
inline constexpr std::uint16_t kOutStart = 0x1100;
inline constexpr std::uint16_t kInStart = 0x1180;
inline constexpr std::uint8_t kOutControl = 0x64;
inline constexpr std::uint8_t kInControl = 0x20;
inline constexpr std::uint16_t kBootOutStart = 0x1800;
inline constexpr std::uint16_t kBootInStart = 0x1C00;
inline constexpr std::uint16_t kBootLength = 0x200;

inline EsmConfig test_esm_config() {
  EsmConfig c;
  c.mailbox_out = {kMbxOutStart, kMbxLength, kMbxOutControl};
  c.mailbox_in = {kMbxInStart, kMbxLength, kMbxInControl};
  c.boot_mailbox_out = {kBootOutStart, kBootLength, kMbxOutControl};
  c.boot_mailbox_in = {kBootInStart, kBootLength, kMbxInControl};
  c.add_process_sm({kSmOutputs, true, kOutStart, kOutControl});
  c.add_process_sm({kSmInputs, false, kInStart, kInControl});
  return c;
}

// Records every hook call; refuses `refuse_to` with `refusal`.
struct RecordingHooks : EsmHooks {
  struct Change {
    AlState from, to;
    AlStatusCode code;
  };
  AlState refuse_to = AlState::Init;
  AlStatusCode refusal = AlStatusCode::NoError;
  std::vector<Change> checks, changes;
  AlStatusCode check_transition(AlState from, AlState to) noexcept override {
    checks.push_back({from, to, AlStatusCode::NoError});
    return to == refuse_to ? refusal : AlStatusCode::NoError;
  }
  void on_state_changed(AlState from, AlState to, AlStatusCode code) noexcept override {
    changes.push_back({from, to, code});
  }
};

class EsmTest : public ::testing::Test {
 protected:
  explicit EsmTest(EsmConfig config = test_esm_config()) : esm(pdi, config) {
    esm.add_hooks(hooks);
    pdi.watchdog_expired(false);  // watchdog running (or disabled)
    esm.reset();
  }

  void request(std::uint16_t control) {
    pdi.master_al_control(control);
    esm.poll();
  }
  std::uint16_t status() const { return pdi.u16(reg::kAlStatus); }
  std::uint16_t code() const { return pdi.u16(reg::kAlStatusCode); }
  bool deactivated(unsigned sm) const {
    return (pdi.u8(static_cast<std::uint16_t>(reg::sync_manager(sm) + reg::sm::kPdiControl)) & 1) != 0;
  }
  void mailbox_sms() {
    pdi.master_sm(0, kMbxOutStart, kMbxLength, kMbxOutControl, true);
    pdi.master_sm(1, kMbxInStart, kMbxLength, kMbxInControl, true);
  }
  void process_sms(std::uint16_t out_len = 4, std::uint16_t in_len = 6) {
    pdi.master_sm(2, kOutStart, out_len, kOutControl, out_len > 0);
    pdi.master_sm(3, kInStart, in_len, kInControl, in_len > 0);
  }
  void go_preop() {
    mailbox_sms();
    request(0x0002);
    ASSERT_EQ(status(), 0x0002);
  }
  void go_safeop() {
    go_preop();
    process_sms();
    request(0x0004);
    ASSERT_EQ(status(), 0x0004);
  }
  void go_op() {
    go_safeop();
    request(0x0008);
    ASSERT_EQ(status(), 0x0008);
  }

  FakePdi pdi;
  RecordingHooks hooks;
  Esm esm;
};

}  // namespace ecat::esc::test
