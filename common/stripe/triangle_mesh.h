#pragma once
// A scene's surfaces as triangles, mm in the table frame (z up, table top
// z = 0), read from Wavefront OBJ text.
//
// OBJ subset: `v x y z [w]` vertices, `f a b c ...` faces (indices from 1,
// negative from the end, `a/t/n` forms accepted, polygons fanned into
// triangles); `vt`, `vn`, `o`, `g`, `s`, `usemtl`, `mtllib`, `l`, comments and
// blank lines ignored. Anything else, a malformed number, a non-finite
// coordinate, a face with fewer than three vertices or an index out of range
// is an error naming the file and line.

#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace ephor::stripe {

class SceneFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;  // mm, table frame
  std::vector<Eigen::Vector3i>
      faces;  // vertex indices (0-based), counter-clockwise seen from outside

  // Bounding box corners (mm); both zero for an empty mesh.
  Eigen::Vector3d min_corner() const;
  Eigen::Vector3d max_corner() const;
  // Appends `other` (its indices shifted).
  void append(const TriangleMesh& other);
};

// Throws SceneFileError ("scene file PATH line N: PROBLEM" or "scene file PATH:
// cannot be read").
TriangleMesh load_obj(const std::string& path);
// Same from text; `name` stands for the file in messages.
TriangleMesh parse_obj(const std::string& text, const std::string& name);
// OBJ text of `mesh` (round-trips through parse_obj), `comment` as leading "# " lines.
std::string to_obj(const TriangleMesh& mesh, const std::string& comment = "");

}  // namespace ephor::stripe
