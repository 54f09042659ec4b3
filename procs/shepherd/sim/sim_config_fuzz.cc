// Fuzz target (issue 18): ephor-sim's configuration file (--config:
// apply_config_file), then the simulator built from it and stepped once, as
// the process does. Bad input must end in ConfigError, or in the
// simulator's std::invalid_argument for a config it refuses.
// Seeds: fuzz_corpus/shepherd_sim_config (sim.example.pbtxt).
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "common/config/text_proto.h"
#include "common/fuzz/fuzz_input.h"
#include "procs/shepherd/sim/sim_config.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static ephor::fuzz::FuzzInputFile file;
  ephor::sim::SimulatorConfig config;
  double fps = 30.0;
  try {
    ephor::sim::apply_config_file(file.write(data, size), config, fps);
    ephor::sim::Simulator sim(config);
    sim.step(1.0 / fps);
  } catch (const ephor::ConfigError&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
