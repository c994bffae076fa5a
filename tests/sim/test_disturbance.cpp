#include <gtest/gtest.h>

#include "../model/test_support.hpp"
#include "tmpc/sim/disturbance.hpp"

namespace tmpc {
namespace {

TEST(DisturbanceSchedule, ThesisStepsAreCumulative) {
  const DisturbanceSchedule s(test::default_config().disturbances);
  EXPECT_EQ(s.force(19.999), Eigen::Vector3d::Zero());
  EXPECT_EQ(s.force(20.0), Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(s.force(39.9), Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(s.force(40.0), Eigen::Vector3d(1, 1, 0));
  EXPECT_EQ(s.force(80.0), Eigen::Vector3d(1, 1, 1));
}

TEST(DisturbanceSchedule, EmptyMeansNoForceAndOrderIsRestored) {
  EXPECT_EQ(DisturbanceSchedule{}.force(100.0), Eigen::Vector3d::Zero());
  const DisturbanceSchedule s({{5.0, Eigen::Vector3d(0, 0, 2)}, {1.0, Eigen::Vector3d(1, 0, 0)}});
  EXPECT_EQ(s.force(2.0), Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(s.force(6.0), Eigen::Vector3d(1, 0, 2));
}

}  // namespace
}  // namespace tmpc
