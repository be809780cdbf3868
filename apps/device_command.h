// `penumbra device [--out FILE] [--validate]`: what Penumbra finds on this machine, as JSON on stdout:
// every Vulkan device the loader lists (and why one is not usable), the one it picks with its driver,
// API version, the extensions and features the passes use (ray queries, acceleration structures,
// geometry shaders, subgroup operations), the limits it sizes buffers by, its memory heaps, and
// what each `auto` setting resolves to there (tracer, shadow-map reads, GPU timer mode).
// Exit 0 when a usable device was found, 2 otherwise (the list is still printed).
#pragma once
#include <string>

#include <CLI/CLI.hpp>

namespace penumbra {

class DeviceCommand {
 public:
  explicit DeviceCommand(CLI::App& app);  // registers the `device` subcommand
  bool parsed() const { return command_->parsed(); }
  int run();

 private:
  CLI::App* command_;
  std::string out_;
  bool validate_ = false;
};

}  // namespace penumbra
