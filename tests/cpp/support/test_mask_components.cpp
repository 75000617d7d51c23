#include <shadecut/support/mask_components.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace shadecut {
namespace {

Mask mask_of(const std::vector<std::string>& rows) {
  Mask mask(Eigen::Index(rows.size()), Eigen::Index(rows[0].size()));
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t c = 0; c < rows[r].size(); ++c) mask(Eigen::Index(r), Eigen::Index(c)) = rows[r][c] == '#';
  return mask;
}

TEST(MaskComponents, LabelsFourConnectedPartsInRasterOrder) {
  // A U-shape joined only at its bottom (one part, though its left arm starts first), a diagonal
  // neighbour (not 4-connected: its own part) and a one-pixel island.
  const Mask mask = mask_of({
      "#.#..#",
      "#.#...",
      "###.#.",
      "......",
      ".....#",
  });
  const MaskComponents found = mask_components(mask);
  EXPECT_EQ(found.count, 4);
  Labels expected(5, 6);
  expected << 0, -1, 0, -1, -1, 1,
              0, -1, 0, -1, -1, -1,
              0, 0, 0, -1, 2, -1,
              -1, -1, -1, -1, -1, -1,
              -1, -1, -1, -1, -1, 3;
  EXPECT_TRUE((found.labels == expected).all()) << found.labels;
}

TEST(MaskComponents, AnEmptyMaskHasNoPart) {
  const MaskComponents found = mask_components(Mask::Constant(3, 4, false));
  EXPECT_EQ(found.count, 0);
  EXPECT_TRUE((found.labels == -1).all());
}

TEST(MaskComponents, ASpiralIsOnePart) {
  // Long thin parts that turn back on themselves join only late in a scan.
  const Mask mask = mask_of({
      "#######",
      "......#",
      "#####.#",
      "#...#.#",
      "#.###.#",
      "#.....#",
      "#######",
  });
  EXPECT_EQ(mask_components(mask).count, 1);
}

}  // namespace
}  // namespace shadecut
