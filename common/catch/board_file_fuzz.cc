// Fuzz target (issue 18): the ball-catching board file as the simulator, the
// vision and the offline tracker read it (--board: load_board_file). A board
// the loader accepts must round-trip through board_to_text(). Bad input must
// end in ConfigError. Seeds: fuzz_corpus/catch_board (deploy/catch/board.pbtxt).
#include <cstddef>
#include <cstdint>

#include "common/catch/board_file.h"
#include "common/config/text_proto.h"
#include "common/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static ephor::fuzz::FuzzInputFile file;
  try {
    const auto board = ephor::catching::load_board_file(file.write(data, size));
    try {
      (void)ephor::catching::parse_board_text(ephor::catching::board_to_text(board, "fuzz"),
                                              "round-trip");
    } catch (const ephor::ConfigError& e) {
      ephor::fuzz::fail(std::string("an accepted board does not round-trip: ") + e.what());
    }
  } catch (const ephor::ConfigError&) {
  }
  return 0;
}
