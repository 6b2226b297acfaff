// A mode's own command-line options (issue 35: a mode is one registered thing). A mode whose
// settings have options no other mode reads declares them here, beside its settings, instead
// of the render command naming them: the render command asks the registry (ModeEntry::options)
// for each mode's, adds them under a heading of their own ("gi options" in render --help), and once
// the command line is parsed lets each set its values on ModeSettings.
#pragma once

#include <CLI/CLI.hpp>

namespace rayproc {

struct ModeSettings;

// Holds the values as parsed, so it must live until apply(): the render command keeps one per
// mode for the command's lifetime.
class ModeOptions {
public:
    virtual ~ModeOptions() = default;
    // Declares the options on the mode's group of the render command.
    virtual void add(CLI::App& group) = 0;
    // The parsed values on the mode's settings, after ModeSettings::forScene: a count the
    // command line did not give keeps the scene's or the default.
    virtual void apply(ModeSettings& settings) const = 0;
};

} // namespace rayproc
