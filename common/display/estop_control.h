#pragma once
// EstopControl: the page's STOP / release button of every system with an arm
// (POST /api/cmd?cmd=estop&value=true|false -> ESTOP estop_t). ephor-arm
// latches a stop; the display repeats a held stop every second (a lost
// message or an arm started later still hears it) and sends a release once
// (a repeated release would undo another sender's stop). DisplayServer does
// the sending; this class holds the state and checks the requests.
//
// Pure; not thread-safe (DisplayServer holds its lock).

#include <optional>
#include <string>

namespace ephor::display {

class EstopControl {
 public:
  // Checks the request's value ("true"/"1" = stop, "false"/"0" = release).
  // Returns the stop state asked for, or nullopt with `why` set.
  static std::optional<bool> parse(const std::optional<std::string>& value, std::string& why);

  // The stop is held (set after the message went out).
  bool held() const { return held_; }
  void set_held(bool stop) { held_ = stop; }

  // estop_t.reason for a stop / a release from the page.
  static const char* reason(bool stop);

 private:
  bool held_ = false;
};

}  // namespace ephor::display
