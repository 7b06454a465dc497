// A walk over blocks lowered onto a flat floor (stages/retarget/terrain_flattening.h), on a synthetic take
// whose blocks, contact phases and body heights are known: every plant lands on the floor, the swings
// between blocks come down across the swing, the body drops by the mean of the feet's blocks, and nothing
// moves horizontally; a walk on the floor is left as it is.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "stages/retarget/terrain_flattening.h"

namespace syn {
namespace {

constexpr int kFrames = 100;
constexpr double kGround = 0.08;  // the ankle landmarks' height on the floor
constexpr double kBand = 0.05;

// Landmarks 0 = pelvis, 1 = left_foot, 2 = right_foot. The left foot stands on the floor over frames
// [0, 20), swings, and stands on a `left_block` over [40, 70); the right foot stands on a `right_block`
// over [10, 50) and on the floor over [80, 100). Swings arc 0.2 m over the straight line between stances.
struct Take {
  LandmarkTrajectories landmarks;
  FootContacts contacts;
};

double Between(double a, double b, int t, int begin, int end) {
  const double s = static_cast<double>(t - begin) / static_cast<double>(end - begin);
  return (1 - s) * a + s * b + 0.2 * std::sin(M_PI * s);
}

Take MakeTake(double left_block, double right_block) {
  Take take;
  LandmarkTrajectories& landmarks = take.landmarks;
  landmarks.names = {"pelvis", "left_foot", "right_foot"};
  landmarks.has_orientation = {false, false, false};
  landmarks.sources = {"", "", ""};
  landmarks.frames = kFrames;
  for (int t = 0; t < kFrames; ++t) {
    const double left = t < 20 ? kGround : t < 40 ? Between(kGround, kGround + left_block, t, 19, 40) : t < 70 ? kGround + left_block
                                                                                                            : kGround + left_block + 0.01 * (t - 69);
    const double right = t < 10 ? kGround + right_block + 0.01 * (10 - t)
                                : t < 50 ? kGround + right_block : t < 80 ? Between(kGround + right_block, kGround, t, 49, 80) : kGround;
    const double pelvis = 0.9 + 0.5 * (left + right);
    const double xs[3] = {0.01 * t, 0.01 * t + 0.1, 0.01 * t - 0.1};
    const double zs[3] = {pelvis, left, right};
    for (int l = 0; l < 3; ++l) {
      const double pose[7] = {xs[l], l == 1 ? 0.1 : l == 2 ? -0.1 : 0.0, zs[l], std::nan(""), std::nan(""), std::nan(""), std::nan("")};
      landmarks.pose.insert(landmarks.pose.end(), pose, pose + 7);
    }
  }
  FootContacts& contacts = take.contacts;
  contacts.frames = kFrames;
  contacts.feet = 2;
  contacts.ground = kGround;
  contacts.phases = {{0, 0, 20}, {0, 40, 70}, {1, 10, 50}, {1, 80, 100}};
  contacts.contact.assign(kFrames * 2, 0);
  for (const ContactPhase& phase : contacts.phases) {
    for (int64_t t = phase.begin; t < phase.end; ++t) contacts.contact[static_cast<size_t>(t * 2 + phase.foot)] = 1;
  }
  return take;
}

double Z(const LandmarkTrajectories& landmarks, int t, int l) { return landmarks.pose[static_cast<size_t>((t * 3 + l) * 7 + 2)]; }
double X(const LandmarkTrajectories& landmarks, int t, int l) { return landmarks.pose[static_cast<size_t>((t * 3 + l) * 7)]; }

TEST(TerrainFlattening, PlantsOnBlocksLandOnTheFloorAndTheBodyComesDownWithThem) {
  Take take = MakeTake(0.15, 0.20);
  const LandmarkTrajectories before = take.landmarks;
  const TerrainFlattening flattening = FlattenTerrain(take.contacts, {1, 2}, kBand, take.landmarks);
  EXPECT_EQ(flattening.raised_phases, 2);
  EXPECT_NEAR(flattening.highest, 0.20, 1e-12);
  const LandmarkTrajectories& after = take.landmarks;
  // Every planted frame's ankle at its on-the-floor height (the left foot's last stance rises 1 cm a frame
  // after frame 69, outside it).
  for (const ContactPhase& phase : take.contacts.phases) {
    for (int64_t t = phase.begin; t < phase.end; ++t) {
      if (phase.foot == 0 && t >= 70) continue;
      EXPECT_NEAR(Z(after, static_cast<int>(t), phase.foot + 1), kGround, 1e-12) << "foot " << phase.foot << " frame " << t;
    }
  }
  // The right foot stood on its block before its first phase too (frame 0 is above the band): lowered by it.
  EXPECT_NEAR(Z(after, 0, 2), kGround + 0.1, 1e-12);
  // The left swing from the floor (frame 19) onto its block (frame 40): lowered linearly across it.
  EXPECT_NEAR(Z(before, 30, 1) - Z(after, 30, 1), 0.15 * (30 - 19) / 21.0, 1e-12);
  // The right swing from its block (49) to the floor (80): the arc kept, the block's height taken out.
  EXPECT_NEAR(Z(after, 65, 2), kGround + 0.2 * std::sin(M_PI * 16 / 31.0), 1e-12);
  // The pelvis by the mean of the feet's levels: at frame 45 both on their blocks.
  EXPECT_NEAR(Z(before, 45, 0) - Z(after, 45, 0), 0.5 * (0.15 + 0.20), 1e-12);
  for (int t = 0; t < kFrames; ++t) {
    for (int l = 0; l < 3; ++l) EXPECT_EQ(X(before, t, l), X(after, t, l));
  }
}

TEST(TerrainFlattening, AWalkOnTheFloorIsLeftAlone) {
  // Plants within the band (a foot on its toes, 3 cm up, is not on a block).
  Take take = MakeTake(0.03, 0.0);
  const LandmarkTrajectories before = take.landmarks;
  const TerrainFlattening flattening = FlattenTerrain(take.contacts, {1, 2}, kBand, take.landmarks);
  EXPECT_EQ(flattening.raised_phases, 0);
  EXPECT_EQ(TerrainFlatteningNote(flattening), "");
  EXPECT_EQ(before.pose.size(), take.landmarks.pose.size());
  for (size_t i = 0; i < before.pose.size(); ++i) {
    if (std::isnan(before.pose[i])) continue;
    EXPECT_EQ(before.pose[i], take.landmarks.pose[i]) << i;
  }
}

TEST(TerrainFlattening, AFootWithoutALandmarkLeavesTheBodyToTheOther) {
  Take take = MakeTake(0.15, 0.20);
  const LandmarkTrajectories before = take.landmarks;
  const TerrainFlattening flattening = FlattenTerrain(take.contacts, {1, -1}, kBand, take.landmarks);
  EXPECT_EQ(flattening.raised_phases, 1);
  EXPECT_NEAR(Z(before, 45, 0) - Z(take.landmarks, 45, 0), 0.15, 1e-12);
  // Landmark 2 is then no foot's: it moves with the body.
  EXPECT_NEAR(Z(before, 45, 2) - Z(take.landmarks, 45, 2), 0.15, 1e-12);
}

}  // namespace
}  // namespace syn
