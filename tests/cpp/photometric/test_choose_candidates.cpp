// The graph cut between candidate normals, on the candidates photometric_stereo leaves.
#include "photometric/photometric_scenes.hpp"

#include <shadecut/photometric/choose_candidates.hpp>
#include <shadecut/support/errors.hpp>

#include <gtest/gtest.h>

#include <random>

namespace shadecut {
namespace {

using testing::degrees_between;
using testing::lights_around;
using testing::outline_costs;
using testing::photographs;

// Mean angle to the truth over the pixels with two candidates, of the choice `pick(p)`.
template <class Pick>
double mean_error_where_two(const NormalCandidates& candidates, const NormalMap& truth, Pick pick) {
  double sum = 0.0;
  int count = 0;
  for (Eigen::Index p = 0; p < truth.size(); ++p) {
    if (candidates.count.data()[p] != 2) continue;
    sum += degrees_between(candidates.normals[std::size_t(pick(p))].xyz.row(p), truth.xyz.row(p));
    ++count;
  }
  return count > 0 ? sum / count : 0.0;
}

double random_choice_error(const NormalCandidates& candidates, const NormalMap& truth) {
  std::mt19937 generator(45);
  std::bernoulli_distribution coin(0.5);
  return mean_error_where_two(candidates, truth, [&](Eigen::Index) { return int(coin(generator)); });
}

TEST(ChooseCandidates, ThreeLitPixelsSettleTheirTwoLitNeighbours) {
  // Three lights around a sphere: where one of them is shadowed, two photographs leave two normals.
  const auto scene = testing::sphere_scene(96, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(3, 50.0, 90.0, 120.0);
  const auto ps = photometric_stereo(photographs(scene, lights, ImageF::Constant(96, 96, 0.6f)), lights, scene.mask);
  const NormalCandidates candidates = photometric_candidates(ps);
  ASSERT_GT(ps.pair_pixels, 200);
  const CandidateCutResult cut = choose_candidates(candidates);
  const double chosen = mean_error_where_two(candidates, scene.normals, [&](Eigen::Index p) { return cut.choice.data()[p]; });
  const double random = random_choice_error(candidates, scene.normals);
  EXPECT_LT(chosen, 0.2);
  EXPECT_GT(random, 10.0 * chosen + 2.0);
  EXPECT_LE(cut.energy, cut.initial_energy);
  for (Eigen::Index p = 0; p < scene.normals.size(); ++p) {
    if (ps.usable.data()[p] >= 3) {
      EXPECT_EQ(cut.normals.xyz.row(p), ps.normals.xyz.row(p));
    }
  }
}

TEST(ChooseCandidates, TwoPhotographsOfASphereWithItsOutline) {
  // Two lights 100 degrees apart and the albedo known: two normals everywhere both light; the
  // outline, where the sphere turns away, says which.
  const auto scene = testing::sphere_scene(96, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(2, 45.0, 0.0, 100.0);
  PhotometricStereoParams params;
  params.albedo = 0.8;
  const auto ps = photometric_stereo(photographs(scene, lights, ImageF::Constant(96, 96, 0.8f)), lights, scene.mask,
                                     {}, params);
  NormalCandidates candidates = photometric_candidates(ps);
  candidates.data_cost = outline_costs(candidates, scene.mask, 1.0);
  const CandidateCutResult cut = choose_candidates(candidates);
  const double chosen = mean_error_where_two(candidates, scene.normals, [&](Eigen::Index p) { return cut.choice.data()[p]; });
  const double facing = mean_error_where_two(candidates, scene.normals, [](Eigen::Index) { return 0; });
  const double random = random_choice_error(candidates, scene.normals);
  EXPECT_LT(chosen, 1.0) << "facing the viewer " << facing << ", random " << random;
  EXPECT_GT(facing, 5.0 * chosen + 2.0);
  EXPECT_GT(random, 5.0 * chosen + 2.0);
  EXPECT_GT(cut.accepted_moves, 0);
}

TEST(ChooseCandidates, ThreeCandidatesAndTheirCosts) {
  // A 1 x 5 strip, its ends fixed at `right`: the middle starts at its cheapest, `up`, and only a move
  // that switches all three middle pixels at once reaches the minimum (any one pixel alone costs more).
  NormalCandidates candidates;
  const Eigen::Vector3f up(0, 0, 1), right(0.6f, 0, 0.8f), left(-0.6f, 0, 0.8f);
  candidates.normals.assign(3, NormalMap(1, 5));
  candidates.count = CountImage::Constant(1, 5, 3);
  candidates.count(0, 0) = candidates.count(0, 4) = 1;
  for (int p = 0; p < 5; ++p) {
    candidates.normals[0].xyz.row(p) = right;
    candidates.normals[1].xyz.row(p) = up;
    candidates.normals[2].xyz.row(p) = left;
  }
  candidates.data_cost.assign(3, ImageF::Zero(1, 5));
  for (int p = 1; p < 4; ++p) {
    candidates.data_cost[0](0, p) = 0.3f;  // the start (cheapest) is `up`
    candidates.data_cost[2](0, p) = 1.0f;
  }
  const CandidateCutResult cut = choose_candidates(candidates);
  // All `right`: 3 x 0.3; all `up`: 2 |right - up| = 1.26.
  EXPECT_EQ(cut.choice(0, 1), 0);
  EXPECT_EQ(cut.choice(0, 2), 0);
  EXPECT_EQ(cut.choice(0, 3), 0);
  EXPECT_NEAR(cut.energy, 0.9, 1e-5);
}

TEST(ChooseCandidates, ACastShadowAmongFourPhotographsIsSettledByItsNeighbours) {
  // Another object's shadow over a disc of photograph 2, a third of its light, on the half of the
  // sphere that turns from that light (from below) but still catches it: every three of the four fit
  // exactly, and the physics alone (a darker photograph is likeliest shadowed where its light grazes)
  // leaves out another photograph in part of the disc (17.9 degrees off there). The pixels around the
  // disc are exact, and the cut carries them in.
  const auto scene = testing::sphere_scene(96, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(4, 40.0, 90.0, 90.0);
  auto images = photographs(scene, lights, ImageF::Constant(96, 96, 0.6f));
  Mask disc = Mask::Constant(96, 96, false);
  for (int r = 0; r < 96; ++r)
    for (int c = 0; c < 96; ++c)
      if ((r - 30) * (r - 30) + (c - 48) * (c - 48) < 8 * 8) {
        images[2](r, c) *= 0.35f;
        disc(r, c) = true;
      }
  const auto ps = photometric_stereo(images, lights, scene.mask);
  ASSERT_FALSE(ps.four_fits.empty());
  const CandidateCutResult cut = choose_candidates(photometric_candidates(ps));
  double physics = 0.0, chosen = 0.0;
  int pixels = 0;
  for (Eigen::Index p = 0; p < scene.normals.size(); ++p) {
    if (!disc.data()[p] || ps.usable.data()[p] != 3) continue;
    physics += degrees_between(ps.normals.xyz.row(p), scene.normals.xyz.row(p));
    chosen += degrees_between(cut.normals.xyz.row(p), scene.normals.xyz.row(p));
    ++pixels;
  }
  ASSERT_GT(pixels, 50);
  EXPECT_GT(physics / pixels, 1.0);
  EXPECT_LT(chosen / pixels, 0.05) << "the physics alone: " << physics / pixels;
}

TEST(ChooseCandidates, WithNothingToChooseEachPixelKeepsItsOneCandidate) {
  // Eight lights around a sphere: three or more light every pixel, so each has one candidate (its fit).
  const auto scene = testing::sphere_scene(64, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(8, 30.0, 90.0, 45.0);
  const auto ps = photometric_stereo(photographs(scene, lights, ImageF::Constant(64, 64, 0.6f)), lights, scene.mask);
  ASSERT_EQ(ps.pair_pixels, 0);
  const NormalCandidates candidates = photometric_candidates(ps);
  ASSERT_TRUE(candidates.data_cost.empty());
  NormalCandidates outside_is_not_zero = candidates;  // a pixel without candidates comes out (0, 0, 0)
  outside_is_not_zero.normals[0].xyz.row(0) << 0.0f, 0.0f, 1.0f;
  ASSERT_EQ(outside_is_not_zero.count.data()[0], 0);
  const CandidateCutResult cut = choose_candidates(outside_is_not_zero);
  for (Eigen::Index p = 0; p < scene.normals.size(); ++p) {
    EXPECT_EQ(cut.choice.data()[p], ps.usable.data()[p] >= 3 ? 0 : -1);
    EXPECT_EQ(cut.normals.xyz.row(p), ps.normals.xyz.row(p));
  }
  EXPECT_EQ(cut.cycles, 0);
  EXPECT_EQ(cut.energy, 0.0);
  EXPECT_EQ(cut.initial_energy, 0.0);
}

TEST(ChooseCandidates, RefusesBadInput) {
  NormalCandidates candidates;
  candidates.normals.assign(2, NormalMap(4, 4));
  candidates.count = CountImage::Constant(4, 4, 2);
  for (auto& map : candidates.normals) map.xyz.col(2).setOnes();
  EXPECT_NO_THROW(choose_candidates(candidates));
  auto too_many = candidates;
  too_many.count(1, 1) = 3;
  EXPECT_THROW(choose_candidates(too_many), InvalidArgument);
  auto wrong_size = candidates;
  wrong_size.normals[1] = NormalMap(4, 5);
  EXPECT_THROW(choose_candidates(wrong_size), InvalidArgument);
  auto negative = candidates;
  negative.data_cost.assign(2, ImageF::Zero(4, 4));
  negative.data_cost[0](2, 2) = -1.0f;
  EXPECT_THROW(choose_candidates(negative), InvalidArgument);
  auto nan = candidates;
  nan.normals[0].xyz(3, 0) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(choose_candidates(nan), InvalidArgument);
  auto infinite = candidates;
  infinite.normals[1].xyz(5, 2) = -std::numeric_limits<float>::infinity();
  EXPECT_THROW(choose_candidates(infinite), InvalidArgument);
  auto infinite_cost = candidates;
  infinite_cost.data_cost.assign(2, ImageF::Zero(4, 4));
  infinite_cost.data_cost[1](0, 3) = std::numeric_limits<float>::infinity();
  EXPECT_THROW(choose_candidates(infinite_cost), InvalidArgument);
  // A candidate a pixel does not have is never read: whatever it holds there is no error.
  auto unread = candidates;
  unread.count(3, 3) = 1;
  unread.normals[1].xyz(15, 0) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NO_THROW(choose_candidates(unread));
  CandidateCutParams zero;
  zero.smoothness = 0.0;
  EXPECT_THROW(choose_candidates(candidates, zero), InvalidArgument);
}

}  // namespace
}  // namespace shadecut
