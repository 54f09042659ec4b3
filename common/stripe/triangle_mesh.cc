#include "common/stripe/triangle_mesh.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace ephor::stripe {

namespace {

[[noreturn]] void fail(const std::string& name, int line, const std::string& what) {
  throw SceneFileError("scene file " + name + " line " + std::to_string(line) + ": " + what);
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  std::string tok;
  while (in >> tok) out.push_back(tok);
  return out;
}

double parse_double(const std::string& tok, const std::string& name, int line) {
  double v = 0.0;
  const char* end = tok.data() + tok.size();
  const auto r = std::from_chars(tok.data(), end, v);
  if (r.ec != std::errc() || r.ptr != end) fail(name, line, "'" + tok + "' is not a number");
  if (!std::isfinite(v)) fail(name, line, "coordinate '" + tok + "' is not finite");
  return v;
}

int parse_index(const std::string& tok, int vertex_count, const std::string& name, int line) {
  // "a", "a/t", "a//n", "a/t/n": the vertex index is before the first slash.
  const std::string head = tok.substr(0, tok.find('/'));
  long v = 0;
  const char* end = head.data() + head.size();
  const auto r = std::from_chars(head.data(), end, v);
  if (head.empty() || r.ec != std::errc() || r.ptr != end)
    fail(name, line, "face index '" + tok + "' is not an integer");
  const long idx = v > 0 ? v - 1 : vertex_count + v;
  if (v == 0 || idx < 0 || idx >= vertex_count)
    fail(name, line,
         "face index " + std::to_string(v) + " out of range (" + std::to_string(vertex_count) +
             " vertices so far)");
  return static_cast<int>(idx);
}

}  // namespace

Eigen::Vector3d TriangleMesh::min_corner() const {
  if (vertices.empty()) return Eigen::Vector3d::Zero();
  Eigen::Vector3d m = vertices.front();
  for (const auto& v : vertices) m = m.cwiseMin(v);
  return m;
}

Eigen::Vector3d TriangleMesh::max_corner() const {
  if (vertices.empty()) return Eigen::Vector3d::Zero();
  Eigen::Vector3d m = vertices.front();
  for (const auto& v : vertices) m = m.cwiseMax(v);
  return m;
}

void TriangleMesh::append(const TriangleMesh& other) {
  const int offset = static_cast<int>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const auto& f : other.faces) faces.push_back(f + Eigen::Vector3i::Constant(offset));
}

TriangleMesh parse_obj(const std::string& text, const std::string& name) {
  TriangleMesh mesh;
  std::istringstream in(text);
  std::string raw;
  int line = 0;
  while (std::getline(in, raw)) {
    ++line;
    if (const auto hash = raw.find('#'); hash != std::string::npos) raw.resize(hash);
    const std::vector<std::string> tok = split(raw);
    if (tok.empty()) continue;
    const std::string& key = tok[0];
    if (key == "v") {
      if (tok.size() < 4 || tok.size() > 5)
        fail(name, line,
             "vertex needs 3 coordinates (x y z [w]), got " + std::to_string(tok.size() - 1));
      mesh.vertices.emplace_back(parse_double(tok[1], name, line), parse_double(tok[2], name, line),
                                 parse_double(tok[3], name, line));
    } else if (key == "f") {
      if (tok.size() < 4)
        fail(name, line, "face needs at least 3 vertices, got " + std::to_string(tok.size() - 1));
      const int n = static_cast<int>(mesh.vertices.size());
      std::vector<int> idx;
      for (size_t i = 1; i < tok.size(); ++i) idx.push_back(parse_index(tok[i], n, name, line));
      for (size_t i = 2; i < idx.size(); ++i) mesh.faces.emplace_back(idx[0], idx[i - 1], idx[i]);
    } else if (key == "vt" || key == "vn" || key == "vp" || key == "o" || key == "g" ||
               key == "s" || key == "usemtl" || key == "mtllib" || key == "l") {
      continue;
    } else {
      fail(name, line, "unknown OBJ statement '" + key + "'");
    }
  }
  if (mesh.faces.empty()) throw SceneFileError("scene file " + name + ": no faces");
  return mesh;
}

TriangleMesh load_obj(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw SceneFileError("scene file " + path + ": cannot be read");
  std::stringstream ss;
  ss << f.rdbuf();
  return parse_obj(ss.str(), path);
}

std::string to_obj(const TriangleMesh& mesh, const std::string& comment) {
  std::ostringstream out;
  out.precision(10);
  std::istringstream c(comment);
  std::string l;
  while (!comment.empty() && std::getline(c, l)) out << "# " << l << "\n";
  for (const auto& v : mesh.vertices) out << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const auto& f : mesh.faces)
    out << "f " << f[0] + 1 << " " << f[1] + 1 << " " << f[2] + 1 << "\n";
  return out.str();
}

}  // namespace ephor::stripe
