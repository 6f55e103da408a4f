#include "dem/wall.hpp"

namespace mfdem::dem {

std::vector<PlaneWall> box_walls(const std::string& name, const Vec3& min, const Vec3& max,
                                 bool open_top, int material) {
  static const char* side_names[3][2] = {{"x-", "x+"}, {"y-", "y+"}, {"z-", "z+"}};
  std::vector<PlaneWall> walls;
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      if (open_top && axis == 2 && side == 1) continue;
      PlaneWall w;
      w.name = name + "." + side_names[axis][side];
      w.point = side == 0 ? min : max;
      w.normal = Vec3::Zero();
      w.normal[axis] = side == 0 ? 1.0 : -1.0;
      w.material = material;
      walls.push_back(w);
    }
  }
  return walls;
}

}  // namespace mfdem::dem
