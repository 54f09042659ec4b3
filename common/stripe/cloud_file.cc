#include "common/stripe/cloud_file.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace ephor::stripe {

namespace {

// PCL's PLY parser asserts (aborts the process) on some malformed headers:
// a list property inside the vertex element (found by fuzz_stripe_cloud_ply
// once a mutation had turned the next "element face" line into garbage). So
// the header is checked here first, strictly, and only a well-formed one
// with one vertex element of scalar properties reaches PCL. Returns why
// not, or "".
std::string ply_header_problem(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "cannot be opened";
  static const std::set<std::string> kScalars = {
      "char", "uchar", "short", "ushort", "int",   "uint",   "float",   "double",
      "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
  std::string line;
  int vertex_elements = 0;
  bool in_vertex = false, any_element = false;
  std::map<std::string, std::string> vertex_properties;  // name -> type
  std::size_t read = 0;
  for (int n = 0; std::getline(in, line); ++n) {
    read += line.size() + 1;
    if (read > 65536) return "no end_header in its first 64 kB";
    // Only printable ASCII, LF line ends and words one space apart: PCL's
    // parser reads a CR or other control byte in ways this check does not
    // (a "\rformat" line made it skip our end_header and assert on a later
    // "obj_info" line, found by fuzz_stripe_cloud_ply), so such a header
    // is refused rather than second-guessed.
    for (const char c : line)
      if (c < 0x20 || c > 0x7e)
        return "header line " + std::to_string(n + 1) +
               " has a control byte (a CR: Windows line ends?) or non-ASCII";
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (n == 0) {
      if (line != "ply") return "it does not begin with 'ply'";
      continue;
    }
    std::vector<std::string> rest;
    for (std::string w; words >> w;) rest.push_back(w);
    if (n == 1 && word != "format") return "header line 2 is not its format";
    // PCL's comment and obj_info callbacks assert that the line begins with
    // the keyword (a leading space aborted the process: fuzz_stripe_cloud_ply).
    if (line.compare(0, word.size(), word) != 0)
      return "header line " + std::to_string(n + 1) + " begins with a space";
    if (word != "comment" && word != "obj_info") {
      std::string canonical = word;
      for (const std::string& w : rest) canonical += " " + w;
      if (line != canonical)
        return "header line " + std::to_string(n + 1) + ": words not one space apart";
    }
    if (word == "end_header" && rest.empty()) {
      if (vertex_elements != 1) return "it has no vertex element, or more than one";
      for (const char* axis : {"x", "y", "z"}) {
        const auto it = vertex_properties.find(axis);
        if (it == vertex_properties.end() || (it->second != "float" && it->second != "float32" &&
                                              it->second != "double" && it->second != "float64"))
          return std::string("no float or double vertex property ") + axis;
      }
      // PCL's colour callbacks assert (abort) unless red, green and blue
      // come together as unsigned bytes (found by fuzz_stripe_cloud_ply).
      int colours = 0;
      for (const char* c : {"red", "green", "blue", "alpha"}) {
        const auto it = vertex_properties.find(c);
        if (it == vertex_properties.end()) continue;
        if (it->second != "uchar" && it->second != "uint8")
          return std::string("vertex property ") + c + " is not uchar";
        colours += std::string(c) != "alpha";
      }
      if (colours != 0 && colours != 3) return "vertex colours without all of red, green, blue";
      return "";
    }
    if (word == "comment" || word == "obj_info") continue;
    if (word == "format") {
      if (rest.size() != 2 || rest[1] != "1.0" ||
          (rest[0] != "ascii" && rest[0] != "binary_little_endian" &&
           rest[0] != "binary_big_endian"))
        return "header line " + std::to_string(n + 1) + ": not a PLY 1.0 format";
      continue;
    }
    if (word == "element") {
      if (rest.size() != 2 || rest[1].empty() || rest[1].size() > 10 ||
          rest[1].find_first_not_of("0123456789") != std::string::npos ||
          std::stoll(rest[1]) > 2147483647LL)
        return "header line " + std::to_string(n + 1) + ": not 'element NAME COUNT'";
      any_element = true;
      in_vertex = rest[0] == "vertex";
      vertex_elements += in_vertex ? 1 : 0;
      continue;
    }
    if (word == "property") {
      if (!any_element)
        return "header line " + std::to_string(n + 1) + ": a property before any element";
      const bool list = rest.size() == 4 && rest[0] == "list" && kScalars.count(rest[1]) != 0 &&
                        kScalars.count(rest[2]) != 0;
      const bool scalar = rest.size() == 2 && kScalars.count(rest[0]) != 0;
      if (!list && !scalar)
        return "header line " + std::to_string(n + 1) + ": not 'property TYPE NAME'";
      if (list && in_vertex) return "a list property in the vertex element";
      const std::string& name = rest.back();
      if (name.empty() ||
          name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                 "0123456789_") != std::string::npos)
        return "header line " + std::to_string(n + 1) + ": a property name that is not a word";
      if (in_vertex) vertex_properties[name] = rest[0];
      continue;
    }
    return "header line " + std::to_string(n + 1) + " is not PLY";
  }
  return "no end_header";
}

}  // namespace

void save_cloud_ply(const std::string& path, const std::vector<Eigen::Vector3d>& points_mm) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.reserve(points_mm.size());
  for (size_t i = 0; i < points_mm.size(); ++i) {
    const Eigen::Vector3d& p = points_mm[i];
    if (!p.allFinite())
      throw CloudFileError("cloud file " + path + ": point " + std::to_string(i) +
                           " is not finite");
    cloud.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                  static_cast<float>(p.z())));
  }
  if (cloud.empty()) {
    // PCL's writer refuses an empty cloud (an empty scan is still a scan):
    // the header alone, as PCL writes it (found by fuzz_stripe_cloud_ply:
    // a cloud of no finite points could not be written).
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << "ply\nformat binary_little_endian 1.0\ncomment PCL generated\nelement vertex 0\n"
           "property float x\nproperty float y\nproperty float z\nend_header\n";
    if (!out.flush()) throw CloudFileError("cloud file " + path + ": cannot be written");
    return;
  }
  // No camera element: PCL's own reader and other tools warn about it.
  pcl::PLYWriter writer;
  if (writer.write(path, cloud, /*binary=*/true, /*use_camera=*/false) < 0)
    throw CloudFileError("cloud file " + path + ": cannot be written");
}

std::vector<Eigen::Vector3d> load_cloud_ply(const std::string& path) {
  // Read into PCL's untyped cloud and take x, y, z out ourselves, after
  // checking that its sizes agree: PCL's own conversion to PointXYZ
  // (fromPCLPointCloud2) trusts them, and a malformed header (an unknown
  // element before the properties) made it index past the points it had
  // allocated (found by fuzz_stripe_cloud_ply, UBSan; a heap overrun without).
  if (const std::string why = ply_header_problem(path); !why.empty())
    throw CloudFileError("cloud file " + path + ": " + why);
  pcl::PCLPointCloud2 blob;
  if (pcl::io::loadPLYFile(path, blob) < 0)
    throw CloudFileError("cloud file " + path + ": cannot be read as PLY");
  const auto bad = [&path](const std::string& why) {
    return CloudFileError("cloud file " + path + ": " + why);
  };
  std::array<std::size_t, 3> offset{};
  std::array<bool, 3> single{};  // float, else double
  const char* const names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    const auto it = std::find_if(blob.fields.begin(), blob.fields.end(),
                                 [&](const pcl::PCLPointField& f) { return f.name == names[k]; });
    if (it == blob.fields.end()) throw bad(std::string("no vertex property ") + names[k]);
    if (it->datatype != pcl::PCLPointField::FLOAT32 && it->datatype != pcl::PCLPointField::FLOAT64)
      throw bad(std::string("vertex property ") + names[k] + " is not float or double");
    const std::size_t size = it->datatype == pcl::PCLPointField::FLOAT32 ? 4 : 8;
    if (std::size_t{it->offset} + size > blob.point_step)
      throw bad("the vertex properties do not fit the vertex size");
    offset[static_cast<std::size_t>(k)] = it->offset;
    single[static_cast<std::size_t>(k)] = size == 4;
  }
  const std::uint64_t width = blob.width, height = blob.height;
  if (width == 0 || height == 0) return {};
  if (std::uint64_t{blob.row_step} < width * blob.point_step ||
      std::uint64_t{blob.data.size()} < height * blob.row_step)
    throw bad("its vertex count disagrees with its data");
  std::vector<Eigen::Vector3d> out;
  out.reserve(static_cast<std::size_t>(width * height));
  for (std::uint64_t row = 0; row < height; ++row) {
    for (std::uint64_t col = 0; col < width; ++col) {
      const std::uint8_t* point = blob.data.data() + row * blob.row_step + col * blob.point_step;
      Eigen::Vector3d p;
      for (std::size_t k = 0; k < 3; ++k) {
        if (single[k]) {
          float v = 0.0f;
          std::memcpy(&v, point + offset[k], sizeof v);
          p[static_cast<Eigen::Index>(k)] = static_cast<double>(v);
        } else {
          double v = 0.0;
          std::memcpy(&v, point + offset[k], sizeof v);
          p[static_cast<Eigen::Index>(k)] = static_cast<double>(v);
        }
      }
      out.push_back(p);
    }
  }
  return out;
}

}  // namespace ephor::stripe
