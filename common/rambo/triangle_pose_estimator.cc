#include "common/rambo/triangle_pose_estimator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <optional>
#include <stdexcept>
#include <unordered_map>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

namespace ephor::rambo {

namespace {

struct Hypothesis {
  Eigen::Matrix3d r;
  Eigen::Vector3d t;
  Eigen::Vector3d centre;  // target centre in the camera frame, mm
  Eigen::Quaterniond q;    // r, for the cheap rotation gate
};

Eigen::Matrix3d edge_frame(const Eigen::Vector3d& e1, const Eigen::Vector3d& e2) {
  const Eigen::Vector3d x = e1.normalized();
  const Eigen::Vector3d z = e1.cross(e2).normalized();
  Eigen::Matrix3d f;
  f << x, z.cross(x), z;
  return f;
}

cv::Mat camera_matrix(const CameraIntrinsics& c) {
  return (cv::Mat_<double>(3, 3) << c.fx_px, 0, c.cx_px, 0, c.fy_px, c.cy_px, 0, 0, 1);
}

std::int64_t cell_key(const Eigen::Vector3d& p, double cell) {
  const auto q = [cell](double v) {
    return static_cast<std::int64_t>(std::floor(v / cell)) & 0x1fffff;
  };
  return (q(p.x()) << 42) | (q(p.y()) << 21) | q(p.z());
}

}  // namespace

std::vector<MatchedTriangle> matched_triangles(const TargetModel& model,
                                               const std::vector<ImageTriple>& triples,
                                               const TrianglePoseResult& result) {
  std::vector<MatchedTriangle> out;
  if (!result.found) return out;
  // The model vertex of an image point (the same point, as estimate() took
  // it from the triples), or -1.
  auto vertex_of = [&](const Eigen::Vector2d& p) {
    for (std::size_t k = 0; k < result.matched_points_px.size(); ++k)
      if ((result.matched_points_px[k] - p).squaredNorm() < 1e-12)
        return result.matched_vertices[k];
    return -1;
  };
  auto joined = [&](int u, int v) {
    const auto& n = model.neighbours()[static_cast<std::size_t>(u)];
    return std::find(n.begin(), n.end(), v) != n.end();
  };
  for (std::size_t i = 0; i < triples.size(); ++i) {
    const int r = vertex_of(triples[i].reference_px);
    const int a = vertex_of(triples[i].a_px);
    const int b = vertex_of(triples[i].b_px);
    if (r < 0 || a < 0 || b < 0 || a == b || !joined(r, a) || !joined(r, b)) continue;
    out.push_back({static_cast<int>(i), {r, a, b}});
  }
  return out;
}

const char* to_string(TrianglePoseMethod m) {
  return m == TrianglePoseMethod::kExactPerspective ? "exact-perspective" : "paraperspective";
}

TrianglePoseEstimator::TrianglePoseEstimator(TargetModel model, CameraIntrinsics camera,
                                             TrianglePoseOptions options)
    : model_(std::move(model)), camera_(camera), options_(options) {
  if (!camera_.valid()) throw std::invalid_argument("TrianglePoseEstimator: bad camera intrinsics");
  if (!(options_.cluster_radius_mm > 0) || !(options_.cluster_rotation_rad > 0) ||
      options_.min_cluster_size < 1 || !(options_.refine_gate_px > 0) ||
      !(options_.final_gate_px > 0) || !(options_.prior_gate_px > 0) || options_.max_triples < 1)
    throw std::invalid_argument(
        "TrianglePoseEstimator: cluster radii, gates, min cluster and max triples must be > 0");
}

int TrianglePoseEstimator::paraperspective_pose(
    const Eigen::Vector3d& ray_r, const Eigen::Vector3d& ray_a, const Eigen::Vector3d& ray_b,
    const Eigen::Vector3d& v_r, const Eigen::Vector3d& v_a, const Eigen::Vector3d& v_b,
    std::vector<Eigen::Isometry3d>* poses) {
  // Standard rotation Q: the reference ray onto the optical axis.
  const Eigen::Matrix3d q =
      Eigen::Quaterniond::FromTwoVectors(ray_r.normalized(), Eigen::Vector3d::UnitZ())
          .toRotationMatrix();
  const Eigen::Vector3d pa = q * ray_a, pb = q * ray_b;
  if (pa.z() <= 1e-9 || pb.z() <= 1e-9) return 0;
  const Eigen::Vector2d u1 = pa.head<2>() / pa.z(), u2 = pb.head<2>() / pb.z();
  const Eigen::Vector3d e1 = v_a - v_r, e2 = v_b - v_r;
  // Scaled orthography about the reference: E_i = (u_i Z, z_i) with
  // |E_i| = |e_i| and E1.E2 = e1.e2 -> quadratic in k = Z^2.
  const double A = e1.squaredNorm(), B = e2.squaredNorm(), C = e1.dot(e2);
  const double a = u1.squaredNorm(), b = u2.squaredNorm(), c = u1.dot(u2);
  const double qa = c * c - a * b, qb = A * b + B * a - 2.0 * C * c, qc = C * C - A * B;
  if (std::abs(qa) < 1e-18 || a < 1e-18 || b < 1e-18) return 0;  // collinear or empty image edges
  const double disc = qb * qb - 4.0 * qa * qc;
  if (disc < 0.0) return 0;
  const double sq = std::sqrt(disc);
  int added = 0;
  for (const double k : {(-qb + sq) / (2.0 * qa), (-qb - sq) / (2.0 * qa)}) {
    if (!(k > 0.0)) continue;
    const double z1sq = A - k * a, z2sq = B - k * b;
    const double tol = 1e-9 * (A + B);
    if (z1sq < -tol || z2sq < -tol) continue;
    const double z_ref = std::sqrt(k);
    double z1 = std::sqrt(std::max(0.0, z1sq)), z2;
    if (z1 > 1e-9 * std::sqrt(A)) {
      z2 = (C - k * c) / z1;
    } else {
      z1 = 0.0;
      z2 = std::sqrt(std::max(0.0, z2sq));
    }
    for (const double sign : {1.0, -1.0}) {
      const Eigen::Vector3d E1(u1.x() * z_ref, u1.y() * z_ref, sign * z1);
      const Eigen::Vector3d E2(u2.x() * z_ref, u2.y() * z_ref, sign * z2);
      if (E1.cross(E2).norm() < 1e-12) continue;
      const Eigen::Matrix3d r_rot = edge_frame(E1, E2) * edge_frame(e1, e2).transpose();
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() = q.transpose() * r_rot;
      pose.translation() = q.transpose() * (Eigen::Vector3d(0, 0, z_ref) - r_rot * v_r);
      poses->push_back(pose);
      ++added;
    }
  }
  return added;
}

TrianglePoseResult TrianglePoseEstimator::estimate(const std::vector<ImageTriple>& triples,
                                                   const Eigen::Isometry3d* prior) const {
  if (triples.size() > static_cast<std::size_t>(options_.max_triples)) {
    TrianglePoseResult refused;
    refused.reason = "more image triples than max_triples (" +
                     std::to_string(options_.max_triples) + "): frame refused";
    return refused;
  }
  TrianglePoseResult pruned = estimate_once(triples, prior);
  if (!prior || (pruned.found && !pruned.ambiguous)) return pruned;
  // Pruning tries only matches near the prior, so a wrong prior (a wrong
  // pose let through, or a motion fitted to one) would never let the true
  // pose be hypothesised again and would hold the estimate on itself: when
  // nothing near the prior stands alone, every match is tried, and a pose
  // that stands alone there wins over the prior.
  TrianglePoseResult all = estimate_once(triples, nullptr);
  all.matches_tried += pruned.matches_tried;
  all.hypotheses += pruned.hypotheses;
  if (all.found) return all;
  pruned.matches_tried = all.matches_tried;
  pruned.hypotheses = all.hypotheses;
  return pruned;
}

TrianglePoseResult TrianglePoseEstimator::estimate_once(const std::vector<ImageTriple>& triples,
                                                        const Eigen::Isometry3d* prior) const {
  TrianglePoseResult res;
  if (triples.empty()) {
    res.reason = "no image triples (no corners joined by edges)";
    return res;
  }
  for (const auto& tr : triples) {
    if (!tr.reference_px.allFinite() || !tr.a_px.allFinite() || !tr.b_px.allFinite()) {
      res.reason = "an image triple has a non-finite pixel coordinate";
      return res;
    }
  }
  const auto& verts = model_.vertices();
  const int nv = static_cast<int>(verts.size());
  // Pruning by the prior: visible vertices and their projections.
  std::vector<bool> prior_visible;
  std::vector<Eigen::Vector2d> prior_px;
  if (prior) {
    prior_visible = model_.visible_vertices(prior->inverse().translation());
    for (const auto& v : verts) {
      const Eigen::Vector3d p = *prior * v;
      prior_px.push_back(p.z() > 1.0 ? camera_.project(p) : Eigen::Vector2d(1e12, 1e12));
    }
  }
  const cv::Mat k = camera_matrix(camera_);
  std::vector<Hypothesis> hyps;
  std::vector<Eigen::Isometry3d> poses;
  std::vector<cv::Point3d> obj(3);
  std::vector<cv::Point2d> img(3);
  std::vector<cv::Mat> rvecs, tvecs;
  const Eigen::Vector3d centre = model_.centre();
  for (const auto& tr : triples) {
    const Eigen::Vector3d ray_r = camera_.ray(tr.reference_px), ray_a = camera_.ray(tr.a_px),
                          ray_b = camera_.ray(tr.b_px);
    for (const auto& mt : model_.triangles()) {
      if (!tr.reference_candidates.empty() &&
          std::find(tr.reference_candidates.begin(), tr.reference_candidates.end(), mt.reference) ==
              tr.reference_candidates.end())
        continue;
      if (prior) {
        const auto r = static_cast<std::size_t>(mt.reference);
        if (!prior_visible[r] || (prior_px[r] - tr.reference_px).norm() > options_.prior_gate_px)
          continue;
      }
      for (int swap = 0; swap < 2; ++swap) {
        const int va = swap ? mt.b : mt.a, vb = swap ? mt.a : mt.b;
        if (prior && ((prior_px[static_cast<std::size_t>(va)] - tr.a_px).norm() >
                          2.0 * options_.prior_gate_px ||
                      (prior_px[static_cast<std::size_t>(vb)] - tr.b_px).norm() >
                          2.0 * options_.prior_gate_px))
          continue;
        ++res.matches_tried;
        const Eigen::Vector3d& pr = verts[static_cast<std::size_t>(mt.reference)];
        const Eigen::Vector3d& pa = verts[static_cast<std::size_t>(va)];
        const Eigen::Vector3d& pb = verts[static_cast<std::size_t>(vb)];
        poses.clear();
        if (options_.method == TrianglePoseMethod::kParaperspective) {
          paraperspective_pose(ray_r, ray_a, ray_b, pr, pa, pb, &poses);
        } else {
          obj[0] = {pr.x(), pr.y(), pr.z()};
          obj[1] = {pa.x(), pa.y(), pa.z()};
          obj[2] = {pb.x(), pb.y(), pb.z()};
          img[0] = {tr.reference_px.x(), tr.reference_px.y()};
          img[1] = {tr.a_px.x(), tr.a_px.y()};
          img[2] = {tr.b_px.x(), tr.b_px.y()};
          rvecs.clear();
          tvecs.clear();
          const int ns = cv::solveP3P(obj, img, k, cv::noArray(), rvecs, tvecs, cv::SOLVEPNP_AP3P);
          for (int s = 0; s < ns; ++s) {
            cv::Mat rm;
            cv::Rodrigues(rvecs[static_cast<std::size_t>(s)], rm);
            Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
            for (int i = 0; i < 3; ++i) {
              for (int j = 0; j < 3; ++j) p.linear()(i, j) = rm.at<double>(i, j);
              p.translation()[i] = tvecs[static_cast<std::size_t>(s)].at<double>(i);
            }
            poses.push_back(p);
          }
        }
        for (const auto& p : poses) {
          if (!p.matrix().allFinite()) continue;
          const Eigen::Vector3d c = p * centre;
          if (c.z() <= 0.0) continue;
          hyps.push_back({p.linear(), p.translation(), c, Eigen::Quaterniond(p.linear())});
        }
      }
    }
  }
  res.hypotheses = static_cast<long>(hyps.size());
  if (hyps.empty()) {
    res.reason = prior ? "no triangle match near the prior pose gave a pose"
                       : "no triangle match gave a pose";
    return res;
  }
  // Cluster: grid cells of the cluster radius; each hypothesis counts its
  // neighbours within the radius and the rotation gate; the best one and
  // its neighbours are the cluster.
  // Wrong matches of a box-like target put many centres near the true one,
  // so the neighbour test runs O(H^2) times in the worst case: the rotation
  // gate is |q1 . q2| >= cos(gate / 2) (no acos, no matrix product).
  const double cell = options_.cluster_radius_mm;
  const double cell2 = cell * cell;
  const double min_qdot = std::cos(options_.cluster_rotation_rad / 2.0);
  std::unordered_map<std::int64_t, std::vector<int>> grid;
  grid.reserve(hyps.size() * 2);
  for (int i = 0; i < static_cast<int>(hyps.size()); ++i)
    grid[cell_key(hyps[static_cast<std::size_t>(i)].centre, cell)].push_back(i);
  auto neighbours = [&](int i, std::vector<int>* out) {
    const Hypothesis& h = hyps[static_cast<std::size_t>(i)];
    int count = 0;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(cell_key(h.centre + cell * Eigen::Vector3d(dx, dy, dz), cell));
          if (it == grid.end()) continue;
          for (int j : it->second) {
            const Hypothesis& g = hyps[static_cast<std::size_t>(j)];
            if ((g.centre - h.centre).squaredNorm() > cell2) continue;
            if (std::abs(g.q.dot(h.q)) < min_qdot) continue;
            ++count;
            if (out) out->push_back(j);
          }
        }
    return count;
  };
  // Candidates: wrong matches of a box-like target put many centres near
  // the true one with other attitudes, so cells are voted in position and
  // rotation (rotation vector quantised by the gate); only members of the
  // fullest cells are scored exactly, O(H) overall instead of O(H^2).
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<int>> cells6;
  for (int i = 0; i < static_cast<int>(hyps.size()); ++i) {
    Eigen::Quaterniond q = hyps[static_cast<std::size_t>(i)].q;
    if (q.w() < 0) q.coeffs() *= -1.0;
    const double vn = q.vec().norm();
    const Eigen::Vector3d rv =
        vn < 1e-12 ? Eigen::Vector3d::Zero() : (2.0 * std::atan2(vn, q.w()) / vn * q.vec()).eval();
    cells6[{cell_key(hyps[static_cast<std::size_t>(i)].centre, cell),
            cell_key(rv, options_.cluster_rotation_rad)}]
        .push_back(i);
  }
  std::vector<const std::vector<int>*> fullest;
  for (const auto& kv : cells6) fullest.push_back(&kv.second);
  const std::size_t top = std::min<std::size_t>(fullest.size(), 8);
  std::partial_sort(fullest.begin(), fullest.begin() + static_cast<long>(top), fullest.end(),
                    [](const auto* a, const auto* b) { return a->size() > b->size(); });
  // Candidate clusters: the hypotheses with most neighbours, at most three
  // that are not neighbours of each other. With refinement, the one that
  // explains most image points (then the lowest reprojection error) wins:
  // a near-symmetric target can give a wrong cluster as many votes.
  std::vector<std::pair<int, int>> scored;  // (neighbours, hypothesis)
  for (std::size_t c = 0; c < top; ++c)
    for (int i : *fullest[c]) scored.emplace_back(neighbours(i, nullptr), i);
  std::sort(scored.begin(), scored.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::pair<int, int>> seeds;
  for (const auto& sc : scored) {
    if (seeds.size() >= 3 || sc.first < options_.min_cluster_size) break;
    const Hypothesis& h = hyps[static_cast<std::size_t>(sc.second)];
    bool distinct = true;
    for (const auto& sd : seeds) {
      const Hypothesis& g = hyps[static_cast<std::size_t>(sd.second)];
      if ((g.centre - h.centre).squaredNorm() <= cell2 && std::abs(g.q.dot(h.q)) >= min_qdot)
        distinct = false;
    }
    if (distinct) seeds.push_back(sc);
  }
  res.cluster_size = scored.empty() ? 0 : scored.front().first;
  if (seeds.empty()) {
    res.reason = "no consistent pose: largest cluster has " + std::to_string(res.cluster_size) +
                 " of " + std::to_string(hyps.size()) + " hypotheses";
    return res;
  }
  // Refinement: distinct image points, matched to visible projected vertices.
  std::vector<Eigen::Vector2d> points;
  auto add_point = [&points](const Eigen::Vector2d& p) {
    for (const auto& q : points)
      if ((q - p).squaredNorm() < 1e-12) return;
    points.push_back(p);
  };
  for (const auto& tr : triples) {
    add_point(tr.reference_px);
    add_point(tr.a_px);
    add_point(tr.b_px);
  }
  auto evaluate = [&](int seed, TrianglePoseResult& r) {
    std::vector<int> members;
    neighbours(seed, &members);
    Eigen::Matrix3d rsum = Eigen::Matrix3d::Zero();
    Eigen::Vector3d tsum = Eigen::Vector3d::Zero();
    for (int j : members) {
      rsum += hyps[static_cast<std::size_t>(j)].r;
      tsum += hyps[static_cast<std::size_t>(j)].t;
    }
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(rsum, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d rmean = svd.matrixU() * svd.matrixV().transpose();
    if (rmean.determinant() < 0) {
      Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
      d(2, 2) = -1;
      rmean = svd.matrixU() * d * svd.matrixV().transpose();
    }
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = rmean;
    pose.translation() = tsum / static_cast<double>(members.size());
    r.target_in_camera = pose;
    if (!options_.refine) return;
    for (const double gate : {options_.refine_gate_px, options_.final_gate_px}) {
      const std::vector<bool> vis = model_.visible_vertices(pose.inverse().translation());
      std::vector<Eigen::Vector2d> proj(static_cast<std::size_t>(nv));
      for (int v = 0; v < nv; ++v)
        proj[static_cast<std::size_t>(v)] =
            camera_.project(pose * verts[static_cast<std::size_t>(v)]);
      std::vector<int> point_of_vertex(static_cast<std::size_t>(nv), -1);
      std::vector<double> dist_of_vertex(static_cast<std::size_t>(nv), gate);
      for (int i = 0; i < static_cast<int>(points.size()); ++i) {
        int bv = -1;
        double bd = gate;
        for (int v = 0; v < nv; ++v) {
          if (!vis[static_cast<std::size_t>(v)]) continue;
          const double d =
              (proj[static_cast<std::size_t>(v)] - points[static_cast<std::size_t>(i)]).norm();
          if (d < bd) bd = d, bv = v;
        }
        if (bv >= 0 && bd < dist_of_vertex[static_cast<std::size_t>(bv)]) {
          dist_of_vertex[static_cast<std::size_t>(bv)] = bd;
          point_of_vertex[static_cast<std::size_t>(bv)] = i;
        }
      }
      std::vector<cv::Point3d> o;
      std::vector<cv::Point2d> m;
      for (int v = 0; v < nv; ++v) {
        const int i = point_of_vertex[static_cast<std::size_t>(v)];
        if (i < 0) continue;
        const auto& p = verts[static_cast<std::size_t>(v)];
        o.emplace_back(p.x(), p.y(), p.z());
        m.emplace_back(points[static_cast<std::size_t>(i)].x(),
                       points[static_cast<std::size_t>(i)].y());
      }
      r.correspondences = static_cast<int>(o.size());
      r.matched_vertices.clear();
      r.matched_points_px.clear();
      for (int v = 0; v < nv; ++v) {
        const int i = point_of_vertex[static_cast<std::size_t>(v)];
        if (i < 0) continue;
        r.matched_vertices.push_back(v);
        r.matched_points_px.push_back(points[static_cast<std::size_t>(i)]);
      }
      if (o.size() < 4) break;
      cv::Mat rm(3, 3, CV_64F), rvec, tvec(3, 1, CV_64F);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) rm.at<double>(i, j) = pose.linear()(i, j);
        tvec.at<double>(i) = pose.translation()[i];
      }
      cv::Rodrigues(rm, rvec);
      if (!cv::solvePnP(o, m, k, cv::noArray(), rvec, tvec, true, cv::SOLVEPNP_ITERATIVE)) break;
      cv::Rodrigues(rvec, rm);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) pose.linear()(i, j) = rm.at<double>(i, j);
        pose.translation()[i] = tvec.at<double>(i);
      }
      double ss = 0.0;
      for (std::size_t i = 0; i < o.size(); ++i) {
        const Eigen::Vector2d pp = camera_.project(pose * Eigen::Vector3d(o[i].x, o[i].y, o[i].z));
        ss += (pp - Eigen::Vector2d(m[i].x, m[i].y)).squaredNorm();
      }
      r.rms_reprojection_px = std::sqrt(ss / static_cast<double>(o.size()));
    }
    r.target_in_camera = pose;
  };
  // The candidates, refined. One stands alone when enough image points fit
  // it, their vertices span 3-D and no other candidate fits as many about
  // as well; else it needs a prior it agrees with (see the header).
  const auto better = [](const TrianglePoseResult& a, const TrianglePoseResult& b) {
    return a.correspondences > b.correspondences || (a.correspondences == b.correspondences &&
                                                     a.rms_reprojection_px < b.rms_reprojection_px);
  };
  std::vector<TrianglePoseResult> cands;
  for (const auto& sd : seeds) {
    TrianglePoseResult r = res;
    r.found = true;
    r.cluster_size = sd.first;
    evaluate(sd.second, r);
    if (!options_.refine) return r;  // the largest cluster, as the paper
    cands.push_back(std::move(r));
  }
  std::sort(cands.begin(), cands.end(), better);
  // Why a candidate cannot stand alone ("" when it can).
  const auto weakness = [&](std::size_t i) -> std::string {
    const TrianglePoseResult& r = cands[i];
    if (r.correspondences < options_.min_correspondences_alone)
      return std::to_string(r.correspondences) + " image points fit it";
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int v : r.matched_vertices) mean += verts[static_cast<std::size_t>(v)];
    mean /= static_cast<double>(r.matched_vertices.size());
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (int v : r.matched_vertices) {
      const Eigen::Vector3d d = verts[static_cast<std::size_t>(v)] - mean;
      scatter += d * d.transpose();
    }
    const Eigen::Vector3d ev =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues();
    const double thickness_mm =
        std::sqrt(std::max(0.0, ev[0]) / static_cast<double>(r.matched_vertices.size()));
    if (thickness_mm < 0.02 * model_.bounding_radius_mm())
      return "its " + std::to_string(r.correspondences) + " image points are one face";
    // The target turned half round about one of its axes through the
    // centre: a box-like target's near-symmetry, which fits every view
    // that does not show what breaks it (the cut corner).
    // About the middle of the bounding box (a cut corner moves the vertex
    // centroid off the box's centre).
    Eigen::Vector3d lo = verts.front(), hi = verts.front();
    for (const auto& v : verts) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const Eigen::Vector3d middle = 0.5 * (lo + hi);
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Isometry3d alt = r.target_in_camera * Eigen::Translation3d(middle) *
                                    Eigen::AngleAxisd(M_PI, Eigen::Vector3d::Unit(axis)) *
                                    Eigen::Translation3d(-middle);
      const std::vector<bool> vis = model_.visible_vertices(alt.inverse().translation());
      int fit = 0;
      double ss = 0.0;
      for (const auto& pt : points) {
        double bd = options_.final_gate_px;
        for (int v = 0; v < nv; ++v) {
          if (!vis[static_cast<std::size_t>(v)]) continue;
          const Eigen::Vector3d pc = alt * verts[static_cast<std::size_t>(v)];
          if (pc.z() <= 1.0) continue;
          bd = std::min(bd, (camera_.project(pc) - pt).norm());
        }
        if (bd < options_.final_gate_px) ++fit, ss += bd * bd;
      }
      const double rms = fit > 0 ? std::sqrt(ss / fit) : 0.0;
      if (fit >= r.correspondences && rms <= 1.5 * r.rms_reprojection_px + 0.5)
        return "the target turned half round fits its " + std::to_string(r.correspondences) +
               " image points as well";
    }
    for (std::size_t j = 0; j < cands.size(); ++j) {
      const TrianglePoseResult& o = cands[j];
      if (j == i || o.correspondences < r.correspondences - 1) continue;
      // As many points about as well, or one fewer clearly better (under
      // 0.8 of its rms): a stray corner (a shading corner near a vertex)
      // lets a wrong pose fit one point more than the truth, at a worse
      // error (seed 2's first frame: 7 points at 2.1 px, the truth 6 at
      // 1.4 px).
      if (o.correspondences < r.correspondences
              ? o.rms_reprojection_px >= 0.8 * r.rms_reprojection_px
              : o.rms_reprojection_px > 1.5 * r.rms_reprojection_px + 0.5)
        continue;
      const double mm = (o.target_in_camera * centre - r.target_in_camera * centre).norm();
      const double rad =
          Eigen::AngleAxisd(o.target_in_camera.linear().transpose() * r.target_in_camera.linear())
              .angle();
      if (mm > options_.cluster_radius_mm || rad > options_.cluster_rotation_rad)
        return "another pose fits its " + std::to_string(r.correspondences) +
               " image points as well";
    }
    return "";
  };
  std::string first_weakness;
  double nearest_mm = -1.0, nearest_deg = 0.0;  // of the weak candidates to the prior
  for (std::size_t i = 0; i < cands.size(); ++i) {
    const std::string why = weakness(i);
    if (why.empty()) return cands[i];
    if (first_weakness.empty()) first_weakness = why;
    if (!prior) continue;
    const double mm = (cands[i].target_in_camera * centre - *prior * centre).norm();
    const double deg =
        Eigen::AngleAxisd(cands[i].target_in_camera.linear().transpose() * prior->linear())
            .angle() *
        180.0 / M_PI;
    if (nearest_mm < 0 || mm < nearest_mm) nearest_mm = mm, nearest_deg = deg;
    if (mm <= options_.prior_agree_mm && deg <= options_.prior_agree_deg) {
      cands[i].ambiguous = true;  // kept with the prior's support
      return cands[i];
    }
  }
  res.cluster_size = seeds.front().first;
  res.ambiguous = true;
  char where[120] = "";
  if (prior)
    std::snprintf(where, sizeof where, " and the nearest is %.0f mm / %.0f deg from the prior",
                  nearest_mm, nearest_deg);
  res.reason = "ambiguous view: " + first_weakness +
               (prior ? std::string(where) : std::string(" and there is no prior"));
  return res;
}

}  // namespace ephor::rambo
