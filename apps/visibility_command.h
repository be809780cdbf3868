// `penumbra visibility --scene S --from RECT --to RECT [--samples NxN]`: patch-to-patch visibility
// (Eisemann & Décoret 2007, section 6) with the bitmask pass: the fraction of unblocked pairs of
// sample points (N x N on each rectangle), printed and written to DIR/visibility.json, with
// DIR/visibility.png (per target sample, the fraction of source samples it sees) and DIR/mask.png
// (one row per target sample, one column per source sample: white where the pair is unblocked).
#pragma once
#include <string>

#include <CLI/CLI.hpp>

namespace penumbra {

class VisibilityCommand {
 public:
  explicit VisibilityCommand(CLI::App& app);  // registers the `visibility` subcommand
  bool parsed() const { return command_->parsed(); }
  int run();

 private:
  CLI::App* command_;
  std::string scene_ = "builtin:courtyard", from_, to_, outDir_ = "out/visibility";
  std::string samples_ = "32x32";
  bool validate_ = false;
};

}  // namespace penumbra
