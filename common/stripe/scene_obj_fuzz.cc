// Fuzz target (issue 18): a scene OBJ file as ephor-stripe-sim and the scan
// planner read it (--scene FILE: StripeScene::load, which parses and builds
// the ray-casting hierarchy), then a few rays cast as the renderer does. Bad
// input must end in SceneFileError. Seeds: fuzz_corpus/stripe_scene_obj
// (deploy/stripe/scenes).
#include <cstddef>
#include <cstdint>

#include "common/fuzz/fuzz_input.h"
#include "common/stripe/stripe_scene.h"
#include "common/stripe/triangle_mesh.h"

using ephor::stripe::StripeScene;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static ephor::fuzz::FuzzInputFile file;
  try {
    const StripeScene scene = StripeScene::load(file.write(data, size));
    const Eigen::Vector3d lo = scene.mesh().min_corner();
    const Eigen::Vector3d hi = scene.mesh().max_corner();
    const Eigen::Vector3d down(0.0, 0.0, -1.0);
    for (int i = 0; i <= 4; ++i) {
      const double s = i / 4.0;
      const Eigen::Vector3d origin(lo.x() + s * (hi.x() - lo.x()), lo.y() + s * (hi.y() - lo.y()),
                                   hi.z() + 100.0);
      (void)scene.first_hit(origin, down, 0.0, 1e6);
      (void)scene.occluded(origin, down, 0.0, 1e6);
    }
    (void)ephor::stripe::to_obj(scene.mesh());
  } catch (const ephor::stripe::SceneFileError&) {
  }
  return 0;
}
