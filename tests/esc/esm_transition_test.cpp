// ESM transition table (ETG.1000.6 §6.4.1; esm-al-codes.md §2): allowed
// transitions, refused ones (0x0011, current state + ErrInd), unknown state
// codes (0x0012), and the services each state runs (SM PDI deactivation).
#include <gtest/gtest.h>

#include "esc/esm_transition.hpp"
#include "esm_fixture.hpp"

namespace ecat::esc::test {
namespace {

TEST(EsmTransitionTable, NamesEveryPair) {
  EXPECT_EQ(lookup_transition(AlState::Init, AlState::PreOp), EsmTransition::IP);
  EXPECT_EQ(lookup_transition(AlState::Init, AlState::Bootstrap), EsmTransition::IB);
  EXPECT_EQ(lookup_transition(AlState::Init, AlState::SafeOp), EsmTransition::Refused);
  EXPECT_EQ(lookup_transition(AlState::Init, AlState::Op), EsmTransition::Refused);
  EXPECT_EQ(lookup_transition(AlState::PreOp, AlState::Op), EsmTransition::Refused);
  EXPECT_EQ(lookup_transition(AlState::PreOp, AlState::Bootstrap), EsmTransition::Refused);
  EXPECT_EQ(lookup_transition(AlState::Bootstrap, AlState::PreOp), EsmTransition::Refused);
  EXPECT_EQ(lookup_transition(AlState::Bootstrap, AlState::Init), EsmTransition::BI);
  EXPECT_EQ(lookup_transition(AlState::SafeOp, AlState::Bootstrap), EsmTransition::Refused);
  EXPECT_EQ(lookup_transition(AlState::Op, AlState::Bootstrap), EsmTransition::Refused);
  EXPECT_EQ(lookup_transition(AlState::Op, AlState::Init), EsmTransition::OI);
  EXPECT_EQ(lookup_transition(AlState::Op, AlState::PreOp), EsmTransition::OP);
  EXPECT_EQ(lookup_transition(AlState::Op, AlState::SafeOp), EsmTransition::OS);
  EXPECT_EQ(lookup_transition(AlState::SafeOp, AlState::Op), EsmTransition::SO);
  EXPECT_EQ(lookup_transition(AlState::SafeOp, AlState::Op), EsmTransition::SO);
  EXPECT_EQ(lookup_transition(AlState::Op, AlState::Op), EsmTransition::Stay);
  EXPECT_FALSE(decode_al_state(0).has_value());
  EXPECT_FALSE(decode_al_state(5).has_value());
  EXPECT_EQ(decode_al_state(8), AlState::Op);
}

TEST_F(EsmTest, ResetIsInitWithAllSmsDeactivated) {
  EXPECT_EQ(status(), 0x0001);
  EXPECT_EQ(code(), 0x0000);
  for (unsigned sm = 0; sm < 4; ++sm) EXPECT_TRUE(deactivated(sm)) << sm;
}

TEST_F(EsmTest, WalksUpToOpAndDownAgainStartingAndStoppingServices) {
  go_preop();
  EXPECT_FALSE(deactivated(0));
  EXPECT_FALSE(deactivated(1));
  EXPECT_TRUE(deactivated(2));
  EXPECT_TRUE(deactivated(3));
  process_sms();
  request(0x0004);
  EXPECT_EQ(status(), 0x0004);
  EXPECT_FALSE(deactivated(2));
  EXPECT_FALSE(deactivated(3));
  request(0x0008);
  EXPECT_EQ(status(), 0x0008);
  EXPECT_EQ(code(), 0x0000);
  request(0x0004);
  EXPECT_EQ(status(), 0x0004);
  request(0x0002);
  EXPECT_EQ(status(), 0x0002);
  EXPECT_TRUE(deactivated(2));
  EXPECT_TRUE(deactivated(3));
  request(0x0001);
  EXPECT_EQ(status(), 0x0001);
  EXPECT_TRUE(deactivated(0));
  ASSERT_EQ(hooks.changes.size(), 6u);
  EXPECT_EQ(hooks.changes[2].from, AlState::SafeOp);
  EXPECT_EQ(hooks.changes[2].to, AlState::Op);
  EXPECT_EQ(hooks.changes[5].to, AlState::Init);
}

TEST_F(EsmTest, GoingDownSkipsChecksAndHooks) {
  go_op();
  const std::size_t checks = hooks.checks.size();
  hooks.refuse_to = AlState::Init;
  hooks.refusal = AlStatusCode::UnspecifiedError;
  pdi.master_sm(0, 0, 0, 0, false);  // even a broken mailbox does not stop Op->Init
  request(0x0001);
  EXPECT_EQ(status(), 0x0001);
  EXPECT_EQ(code(), 0x0000);
  EXPECT_EQ(hooks.checks.size(), checks);
  for (unsigned sm = 0; sm < 4; ++sm) EXPECT_TRUE(deactivated(sm)) << sm;
}

TEST_F(EsmTest, OpToPreOpDirectly) {
  go_op();
  request(0x0002);
  EXPECT_EQ(status(), 0x0002);
  EXPECT_EQ(code(), 0x0000);
}

struct Refusal {
  std::uint16_t from;
  std::uint16_t request;
};

class EsmRefusedTest : public EsmTest, public ::testing::WithParamInterface<Refusal> {};

TEST_P(EsmRefusedTest, RefusedWithCurrentStatePlusErrInd) {
  const Refusal r = GetParam();
  if (r.from >= 0x0002) go_preop();
  if (r.from >= 0x0004) {
    process_sms();
    request(0x0004);
  }
  if (r.from == 0x0008) request(0x0008);
  ASSERT_EQ(status(), r.from);
  const std::size_t changes = hooks.changes.size();
  request(r.request);
  EXPECT_EQ(status(), r.from | 0x0010);
  EXPECT_EQ(code(), 0x0011);
  EXPECT_EQ(hooks.changes.size(), changes);
}

INSTANTIATE_TEST_SUITE_P(Table, EsmRefusedTest,
                         ::testing::Values(Refusal{0x0001, 0x0004}, Refusal{0x0001, 0x0008},
                                           Refusal{0x0002, 0x0008}, Refusal{0x0002, 0x0003},
                                           Refusal{0x0004, 0x0003}, Refusal{0x0008, 0x0003}));

class EsmUnknownStateTest : public EsmTest, public ::testing::WithParamInterface<std::uint16_t> {};

TEST_P(EsmUnknownStateTest, UnknownRequestedState) {
  go_preop();
  request(GetParam());
  EXPECT_EQ(status(), 0x0012);
  EXPECT_EQ(code(), 0x0012);
}

INSTANTIATE_TEST_SUITE_P(Codes, EsmUnknownStateTest,
                         ::testing::Values(0x0000, 0x0005, 0x0006, 0x0007, 0x0009, 0x000F, 0x0015));

TEST_F(EsmTest, RepeatedRequestForCurrentStateChangesNothing) {
  go_preop();
  const std::size_t changes = hooks.changes.size();
  request(0x0002);
  EXPECT_EQ(status(), 0x0002);
  EXPECT_EQ(code(), 0x0000);
  EXPECT_EQ(hooks.changes.size(), changes);
}

TEST_F(EsmTest, NoEventNoAction) {
  mailbox_sms();
  pdi.poke_u16(reg::kAlControl, 0x0002);  // written without the event bit
  esm.poll();
  EXPECT_EQ(status(), 0x0001);
}

}  // namespace
}  // namespace ecat::esc::test
