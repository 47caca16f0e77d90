#include "rabbit/control/terrain_command.h"

#include <algorithm>
#include <cmath>

namespace rabbit {

GradeView GradeAround(const Terrain* terrain, const Vec2& landing, const Vec2& other_foot,
                      double l_step) {
  GradeView view;
  if (terrain == nullptr || std::abs(landing.x() - other_foot.x()) < 0.01) return view;
  const double ahead = GradeAhead(terrain->ground, landing.x(),
                                  landing.x() + std::clamp(l_step, 0.15, 0.6));
  const double between = GradeAhead(terrain->ground, std::min(landing.x(), other_foot.x()),
                                    std::max(landing.x(), other_foot.x()));
  view.change = ahead - between;
  view.level = ahead == 0.0 && between == 0.0;
  return view;
}

bool OpenLevelGround(const Terrain* terrain, double x_from, double x_to) {
  if (terrain == nullptr) return true;
  const GroundProfile& ground = terrain->ground;
  return ground.SegmentAt(x_from) == ground.SegmentAt(x_to) && ground.SlopeAt(x_from) == 0.0 &&
         terrain->SurfaceAt(x_from) == kGround &&
         terrain->DistanceToNextObstacle(x_from) > x_to - x_from;
}

double TerrainSpeedCommand(const Terrain* terrain, const SlopeAdaptation& slope,
                           const StepPlannerParams& planner, const TerrainSteps& steps, double v_d,
                           const Vec2& landing, const Vec2& other_foot) {
  if (terrain == nullptr) return steps.SpeedCommand(v_d);
  const double v_slope = slope.SpeedCommand(v_d, terrain->ground, landing.x());
  const double v_obstacle =
      planner.enabled
          ? ApproachSpeed(planner, terrain->obstacles, std::min(landing.x(), other_foot.x()),
                          std::max(landing.x(), other_foot.x()), v_slope)
          : v_slope;
  return steps.SpeedCommand(v_obstacle);
}

}  // namespace rabbit
