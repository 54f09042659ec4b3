#pragma once
// Loading Protobuf text-format configuration with errors that name the file,
// the line and the field.

#include <memory>
#include <stdexcept>
#include <string>

#include <google/protobuf/message.h>
#include <google/protobuf/text_format.h>

namespace ephor {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A parsed text proto plus where each field was written, so semantic checks
// after parsing can still point at a line.
class TextProto {
 public:
  // Parses `path` into `message` (which must outlive this object). Throws
  // ConfigError "path:line:column: problem" on a syntax error, an unknown
  // field or a missing file.
  TextProto(const std::string& path, google::protobuf::Message* message);
  // Same, from text in memory; `name` stands for the file in messages.
  static std::unique_ptr<TextProto> from_string(const std::string& text, const std::string& name,
                                                google::protobuf::Message* message);

  const std::string& path() const { return path_; }

  // Throws ConfigError "path:line: field_path: problem". `field_path` is like
  // "process[2].task[0].period_ms"; the line is that of the field when it was
  // written in the file, else of its nearest written parent.
  [[noreturn]] void fail(const std::string& field_path, const std::string& problem) const;

 private:
  TextProto(std::string path, google::protobuf::Message* message, const std::string& text);
  std::string path_;
  google::protobuf::Message* message_;
  google::protobuf::TextFormat::ParseInfoTree tree_;
};

}  // namespace ephor
