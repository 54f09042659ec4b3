#include "common/config/text_proto.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <google/protobuf/io/tokenizer.h>

namespace ephor {
namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::TextFormat;

class CollectFirstError : public google::protobuf::io::ErrorCollector {
 public:
  void AddError(int line, int column, const std::string& message) override {
    if (!has_error) {
      // The parser counts from 0; editors count from 1.
      first = std::to_string(line + 1) + ":" + std::to_string(column + 1) + ": " + message;
      has_error = true;
    }
  }
  void AddWarning(int, int, const std::string&) override {}
  bool has_error = false;
  std::string first;
};

struct PathStep {
  std::string field;
  int index = -1;  // -1: not repeated
};

std::vector<PathStep> split_path(const std::string& path) {
  std::vector<PathStep> steps;
  std::stringstream ss(path);
  std::string part;
  while (std::getline(ss, part, '.')) {
    PathStep step;
    const auto bracket = part.find('[');
    step.field = part.substr(0, bracket);
    if (bracket != std::string::npos) step.index = std::stoi(part.substr(bracket + 1));
    steps.push_back(step);
  }
  return steps;
}

std::string read_file(const std::string& path) {
  // A folder opens as an empty stream on Linux: it would parse as an empty
  // message, and a process would start with every default (issue 18).
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw ConfigError(path + ": is a folder, not a file");
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open file");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

TextProto::TextProto(const std::string& path, google::protobuf::Message* message)
    : TextProto(path, message, read_file(path)) {}

std::unique_ptr<TextProto> TextProto::from_string(const std::string& text, const std::string& name,
                                                  google::protobuf::Message* message) {
  return std::unique_ptr<TextProto>(new TextProto(name, message, text));
}

TextProto::TextProto(std::string path, google::protobuf::Message* message, const std::string& text)
    : path_(std::move(path)), message_(message) {
  CollectFirstError errors;
  TextFormat::Parser parser;
  parser.RecordErrorsTo(&errors);
  parser.WriteLocationsTo(&tree_);
  if (!parser.ParseFromString(text, message_)) {
    throw ConfigError(path_ + ":" + (errors.has_error ? errors.first : "cannot parse"));
  }
}

void TextProto::fail(const std::string& field_path, const std::string& problem) const {
  // Walk the field path through the parse-info tree to the deepest location
  // that was actually written in the file.
  const TextFormat::ParseInfoTree* tree = &tree_;
  const Descriptor* descriptor = message_->GetDescriptor();
  int line = -1;
  for (const PathStep& step : split_path(field_path)) {
    if (tree == nullptr || descriptor == nullptr) break;
    const FieldDescriptor* field = descriptor->FindFieldByName(step.field);
    if (field == nullptr) break;
    // A repeated field named without an index ("vertex" for the whole list)
    // has no one line: keep its parent's (protobuf's index check fires on -1
    // there), and an index on a single field means nothing.
    if (field->is_repeated() && step.index < 0) break;
    const int index = field->is_repeated() ? step.index : -1;
    const auto loc = tree->GetLocation(field, index);
    if (loc.line >= 0) line = loc.line;
    if (field->type() != FieldDescriptor::TYPE_MESSAGE) break;
    tree = tree->GetTreeForNested(field, index);
    descriptor = field->message_type();
  }
  const std::string where = line >= 0 ? path_ + ":" + std::to_string(line + 1) : path_;
  throw ConfigError(where + ": " + field_path + ": " + problem);
}

}  // namespace ephor
