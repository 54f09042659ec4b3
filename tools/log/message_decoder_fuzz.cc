// Fuzz target (issue 18): one recorded message as `tools/ephor log export`
// and `log info` decode it (MessageDecoder, by the schema read from
// lcmtypes/*.lcm): the type found by the fingerprint, then every field, with
// counts and strings as they come. Bad input must end in DecodeError.
// Seeds: fuzz_corpus/lcm_message (encoded arm_cmd_t, camera_frame_t, ...).
#include <cstddef>
#include <cstdint>

#include "common/config/repo_paths.h"
#include "tools/log/lcm_schema.h"
#include "tools/log/message_decoder.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const ephor::logtools::LcmSchema schema =
      ephor::logtools::LcmSchema::load_directory(ephor::resolve_repo_path("lcmtypes"));
  static const ephor::logtools::MessageDecoder decoder(schema, {true});
  try {
    // Dumped as tools/ephor log export does (bad UTF-8 replaced).
    (void)decoder.decode(data, size)
        .fields.dump(-1, ' ', false, ephor::logtools::Json::error_handler_t::replace);
  } catch (const ephor::logtools::DecodeError&) {
  }
  return 0;
}
