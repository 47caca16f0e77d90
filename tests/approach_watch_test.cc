// The approach watch (approach_watch.h): a step whose v_orb leaves the same leg's last
// undisturbed step's by more than the dead zone is disturbed, and the reference stays the
// undisturbed one; a change of command leaves the steps from it unjudged; off, nothing is ever
// disturbed; the key is off in the library and on in the adaptive preset, and bad values are
// refused with the key's name.
#include "rabbit/control/approach_watch.h"

#include <gtest/gtest.h>

#include <string>

#include "rabbit/control/step_planner.h"
#include "rabbit/control/walker_presets.h"

namespace rabbit {
namespace {

// One step of 0.5 s at 1 kHz from t0: v_orb = v, or v + push from s = 0.3 on; the command v_c
// for the step given after the touchdown, as the walker does.
void Step(ApproachWatch* w, double t0, double v, double push = 0.0, double v_c = 0.6,
          bool own = true, bool level = true) {
  w->OnTouchdown(t0, 0.5);
  w->Command(v_c, level);
  for (int k = 0; k < 500; ++k) w->Observe(t0 + 1e-3 * k, v + (k >= 150 ? push : 0.0), own);
}

// Walks n steps from t = 0 at 0.5 m/s (the first two set the timebases, the next two the
// references, then the kSettleSteps from the first command are unjudged).
double Walk(ApproachWatch* w, int n) {
  for (int i = 0; i < n; ++i) Step(w, 0.5 * i, 0.5);
  return 0.5 * n;
}

TEST(ApproachWatchTest, APushDisturbsItsStepAndTheReferenceStays) {
  ApproachWatch w(0.3);
  double t = Walk(&w, 8);
  Step(&w, t, 0.5);
  EXPECT_FALSE(w.last_disturbed());
  Step(&w, t += 0.5, 0.5, 0.4);  // pushed: 0.4 m/s above the reference from s = 0.3
  Step(&w, t += 0.5, 0.5);       // its touchdown ends the pushed step
  EXPECT_TRUE(w.last_disturbed());
  EXPECT_NEAR(w.last_d(), 0.4, 1e-9);
  // The leg's next step, undisturbed, is compared with the step before the push.
  Step(&w, t += 0.5, 0.5);
  EXPECT_FALSE(w.last_disturbed());
  Step(&w, t += 0.5, 0.5);
  EXPECT_FALSE(w.last_disturbed());
  // Backward, and within the dead zone.
  Step(&w, t += 0.5, 0.5, -0.35);
  Step(&w, t += 0.5, 0.5);
  EXPECT_TRUE(w.last_disturbed());
  EXPECT_NEAR(w.last_d(), -0.35, 1e-9);
  Step(&w, t += 0.5, 0.5, 0.25);
  Step(&w, t += 0.5, 0.5);
  EXPECT_FALSE(w.last_disturbed());
}

TEST(ApproachWatchTest, AChangeOfCommandIsNoPush) {
  ApproachWatch w(0.3);
  double t = Walk(&w, 8);
  // The command steps up and v_orb with it, by more than the dead zone: the kSettleSteps steps
  // from the change are not judged, and become the references.
  for (int i = 0; i < ApproachWatch::kSettleSteps; ++i) {
    Step(&w, t, 0.9, 0.0, 0.7);
    t += 0.5;
    EXPECT_FALSE(w.last_disturbed());
  }
  for (int i = 0; i < 4; ++i) {
    Step(&w, t, 0.9, 0.0, 0.7);
    t += 0.5;
    EXPECT_FALSE(w.last_disturbed());
  }
  // Off level ground (a grade, a step's face) likewise.
  Step(&w, t += 0.5, 0.5, 0.0, 0.7, true, false);
  for (int i = 1; i < ApproachWatch::kSettleSteps + 4; ++i) {
    Step(&w, t += 0.5, 0.5, 0.0, 0.7);
    EXPECT_FALSE(w.last_disturbed());
  }
  t += 0.5;
  // The same jump on level ground and without a change of command is a push.
  Step(&w, t, 0.9, 0.0, 0.7);
  Step(&w, t += 0.5, 0.9, 0.0, 0.7);
  EXPECT_TRUE(w.last_disturbed());
}

TEST(ApproachWatchTest, OutsideTheWalkersOwnStepsTheReferencesAreForgotten) {
  ApproachWatch w(0.3);
  double t = Walk(&w, 8);
  Step(&w, t, 0.5, 0.0, 0.6, false);  // the step over
  // Back to the walker's steps at another speed: nothing to compare with until the references
  // are learnt again.
  for (int i = 0; i < 5; ++i) {
    Step(&w, t += 0.5, 0.9);
    EXPECT_FALSE(w.last_disturbed());
  }
}

TEST(ApproachWatchTest, OffNothingIsDisturbed) {
  ApproachWatch w(0.0);
  EXPECT_FALSE(w.enabled());
  double t = Walk(&w, 8);
  Step(&w, t, 0.5, 1.0);
  Step(&w, t += 0.5, 0.5);
  EXPECT_FALSE(w.last_disturbed());
}

TEST(ApproachWatchTest, KeyDefaultsAndValidation) {
  EXPECT_EQ(StepPlannerParams{}.push_dead, 0.0);
  EXPECT_EQ(PresetWalkerParams(WalkerPreset::kAdaptive).planner.push_dead, 0.0);  // off
  EXPECT_FALSE(PresetWalkerParams(WalkerPreset::kChapter).planner.enabled);
  StepPlannerParams p;
  std::string error;
  EXPECT_TRUE(p.IsValid(&error));
  for (double bad : {-0.1, 2.5, std::nan("")}) {
    p.push_dead = bad;
    EXPECT_FALSE(p.IsValid(&error));
    EXPECT_NE(error.find("planner.push_dead"), std::string::npos) << error;
  }
}

}  // namespace
}  // namespace rabbit
