#pragma once
// The target's pose in the camera frame from image triangles (RAMBO paper,
// section 5; Linnainmaa, Harwood and Davis's triangle pairs): every image
// triple (reference vertex + two joined vertices) is matched to every model
// triangle (vertex + two joined vertices, both ways round), each match gives
// up to four poses (exact perspective) or two (paraperspective), and the
// poses are clustered: the largest cluster is the target's pose.
//
// Pose of one triangle pair:
//   kExactPerspective  the perspective-3-point problem, solved with OpenCV's
//                      cv::solveP3P (flag SOLVEPNP_AP3P, Ke and Roumeliotis).
//   kParaperspective   the paper's method without its look-up tables: the
//                      standard rotation (the camera turned about its centre
//                      so the reference vertex is on the optical axis), then
//                      the paraperspective projection about the reference
//                      vertex, which on the axis is a scaled orthographic one;
//                      the triangle's orientation is then the closed-form
//                      root of a quadratic in the squared depth (two mirror
//                      solutions, the paper's "two possible orientations")
//                      and its distance comes from the size. Error of order
//                      (triangle depth / distance); the CM-2 read the same
//                      quantities from 2D tables, we compute them.
// Clustering: the paper clusters the projections of the target's centre; we
// cluster the centre's 3-D position (grid hashing, radius cluster_radius_mm)
// with a rotation gate, which also separates poses that share a centre
// projection but not a depth or attitude.
// Refinement (beyond the paper): the cluster's pose matches every image
// point to the nearest visible model vertex's projection and is refined by
// OpenCV's iterative PnP (Levenberg-Marquardt on reprojection error).
// Pruning (section 5): with a prior pose from the last few consistent
// estimates, only matches whose model reference vertex is visible and
// projects within prior_gate_px of the image reference vertex are tried.
// Ambiguous views (beyond the paper): a pose is kept on its own only when
// at least min_correspondences_alone image points fit it, their model
// vertices are not all in one plane (a view of one face of a box-like
// target: the face turned half round fits as well), the target turned half
// round about one of its axes through the centre does not fit them as well
// (a box's symmetry, broken only where the cut corner is seen) and no
// other candidate fits as many points about as well. Otherwise it is "no pose" without a
// prior and, with one, kept only when it agrees with the prior
// (prior_agree_mm of the centre, prior_agree_deg). A pose that stands on its
// own is kept even far from the prior: the prior may be the one that is
// wrong. So that a wrong prior cannot hide such a pose by pruning it away,
// a pruned search that finds nothing standing alone is followed by the
// unpruned one. A candidate also needs no rival that fits one image point
// fewer strictly better: a stray corner near a vertex can let a wrong pose
// fit one point more than the truth does.

#include <optional>
#include <string>
#include <vector>

#include "common/rambo/image_triple.h"
#include "common/rambo/target_model.h"

namespace ephor::rambo {

enum class TrianglePoseMethod { kExactPerspective, kParaperspective };
const char* to_string(TrianglePoseMethod m);

struct TrianglePoseOptions {
  TrianglePoseMethod method = TrianglePoseMethod::kExactPerspective;
  double cluster_radius_mm = 20.0;     // centre positions within this are one cluster
  double cluster_rotation_rad = 0.15;  // and orientations within this
  int min_cluster_size = 3;            // fewer votes: "no pose"
  bool refine = true;
  double refine_gate_px = 12.0;       // first matching of image points to projected vertices
  double final_gate_px = 3.0;         // second matching, after the first refinement
  double prior_gate_px = 25.0;        // pruning with a prior pose
  int min_correspondences_alone = 5;  // image points a pose needs without a prior's support
  double prior_agree_mm = 30.0;       // a weaker pose's centre this near the prior's
  double prior_agree_deg = 10.0;      // and its attitude this near
  // A frame with more image triples than this is refused ("no pose", its
  // reason naming the cap): the estimate's time grows with the triples
  // (about 1.2 ms each, -O3, the built-in target; twice that with a prior
  // not confirmed), so a frame with thousands (a bad or hostile features
  // message: nothing else bounds it) would hold the pose task for seconds.
  // The features process finds 10-30 on the target (at most 40 corners).
  int max_triples = 64;
};

struct TrianglePoseResult {
  bool found = false;
  std::string reason;                                                  // when not found
  Eigen::Isometry3d target_in_camera = Eigen::Isometry3d::Identity();  // mm
  long matches_tried = 0;             // image triangle x model triangle x assignment pairs solved
  long hypotheses = 0;                // poses those gave (clustered)
  int cluster_size = 0;               // hypotheses in the winning cluster
  int correspondences = 0;            // image points matched to model vertices after refinement
  std::vector<int> matched_vertices;  // their model vertices
  std::vector<Eigen::Vector2d> matched_points_px;  // and those image points, same order
  bool ambiguous = false;  // found only with the prior's support (see above), or why not found
  double rms_reprojection_px = 0.0;
};

// An image triple that a found pose matches to a model triangle: each of
// its three points is one of the result's matched image points, and the
// model vertices of the two joined points are joined to the reference's on
// the model (for the page, procs/rambo/display).
struct MatchedTriangle {
  int triple = -1;         // index into the triples given to estimate()
  ModelTriangle vertices;  // reference, a, b as in the triple (a, b not sorted)
};
std::vector<MatchedTriangle> matched_triangles(const TargetModel& model,
                                               const std::vector<ImageTriple>& triples,
                                               const TrianglePoseResult& result);

class TrianglePoseEstimator {
 public:
  // Throws std::invalid_argument for bad intrinsics or options.
  TrianglePoseEstimator(TargetModel model, CameraIntrinsics camera, TrianglePoseOptions options);

  // prior: the target's expected pose in the camera frame (prunes matches).
  TrianglePoseResult estimate(const std::vector<ImageTriple>& triples,
                              const Eigen::Isometry3d* prior = nullptr) const;

  const TargetModel& model() const { return model_; }
  const CameraIntrinsics& camera() const { return camera_; }
  const TrianglePoseOptions& options() const { return options_; }

  // One triangle pair by the paraperspective method: rays (x, y, 1) of the
  // reference and the two joined image points, the matching model points
  // (mm). Appends up to two poses (model -> camera). Exposed for tests.
  static int paraperspective_pose(const Eigen::Vector3d& ray_r, const Eigen::Vector3d& ray_a,
                                  const Eigen::Vector3d& ray_b, const Eigen::Vector3d& v_r,
                                  const Eigen::Vector3d& v_a, const Eigen::Vector3d& v_b,
                                  std::vector<Eigen::Isometry3d>* poses);

 private:
  // One search: pruned by the prior when there is one (estimate() adds the
  // unpruned search when nothing near the prior stands alone).
  TrianglePoseResult estimate_once(const std::vector<ImageTriple>& triples,
                                   const Eigen::Isometry3d* prior) const;
  TargetModel model_;
  CameraIntrinsics camera_;
  TrianglePoseOptions options_;
};

}  // namespace ephor::rambo
