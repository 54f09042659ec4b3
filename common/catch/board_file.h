#pragma once
// The board file (Protobuf text, schema board.proto): the board's size, the
// ball and the four black circles, mm in the board frame B of board_model.h.
//
//   width_mm: 600  height_mm: 900  ball_diameter_mm: 40
//   circle { x_mm: 60  y_mm: 60  diameter_mm: 70 }   # top-left
//   circle { x_mm: 540 y_mm: 60  diameter_mm: 50 }   # top-right
//   circle { x_mm: 60  y_mm: 840 diameter_mm: 50 }   # bottom-left
//   circle { x_mm: 540 y_mm: 840 diameter_mm: 50 }   # bottom-right

#include <string>

#include "common/catch/board_model.h"

namespace ephor::catching {

// Reads and checks a board file. Throws ephor::ConfigError (a
// std::runtime_error) whose message starts "board file <path>" and names the
// problem and, where it was written, the line: unreadable file, syntax error,
// a missing or non-finite or non-positive size, not exactly four circles, a
// circle outside the board, circles out of their corner order, a ball wider
// than the board.
BoardSpec load_board_file(const std::string& path);
// Same from text in memory; `name` stands for the file in messages.
BoardSpec parse_board_text(const std::string& text, const std::string& name);

// The board as board-file text (round-trips through parse_board_text), each
// line of `header_comment` written as a leading "# " comment.
std::string board_to_text(const BoardSpec& board, const std::string& header_comment = "");
// Checks `board` as the loader would, then writes it. Throws ConfigError.
void save_board_file(const BoardSpec& board, const std::string& path,
                     const std::string& header_comment = "");

// The names the loaders and the vision use for circles[0..3].
const char* circle_name(int index);  // "top-left", "top-right", "bottom-left", "bottom-right"

}  // namespace ephor::catching
