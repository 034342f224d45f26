// What every stage shares. A stage is one tool's work as a library call: read the input file,
// run the tool's algorithms, write the output atomically, build the JSON report. The tool's main
// only parses flags into the stage's settings, validates them and maps errors to exit codes.
//
// Stages print nothing: warnings and progress go to the callbacks in StageCommon, statistics
// come back as text in StageResult for the tool to print with -v.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"

namespace lodbake {

enum class ImageCheck;  // lodbake/texture/codec.h

// Settings every stage takes (the flags -i, -o, --report, -v, --threads).
struct StageCommon {
    std::string input;   // glTF to read (.gltf or .glb)
    std::string output;  // file to write; .glb or .gltf chosen by its extension
    std::string report;  // JSON report to write; empty = none
    int verbose = 0;     // > 0: StageResult::statistics holds the statistics text
    int threads = 0;     // worker threads, 0 = all cores; output is identical for any count
    std::function<bool(double)> progress;             // fraction done; may be empty
    std::function<void(const std::string&)> warning;  // each warning of the input, as soon as it is read; may be empty
    // In memory instead of files (the lodbake chain, lodbake/stages/chain.h). When inputBytes is
    // set, the stage reads these bytes instead of the file `input` (messages and the report still
    // name `input`) and takes them: they are empty once it has loaded its input. When outputBytes is set, a stage that writes a multiresolution glTF
    // (writeStageOutput) encodes it there, as the .glb it would write to `output`, instead of
    // writing the file.
    std::vector<unsigned char>* inputBytes = nullptr;
    std::vector<unsigned char>* outputBytes = nullptr;
    // Every image of the input was decoded in full by an earlier stage of this process (the lodbake
    // chain hands its own intermediates on): loading checks image headers only.
    bool inputImagesDecoded = false;
};

struct StageResult {
    nlohmann::json report;   // also written to StageCommon::report when that is set
    std::string statistics;  // lines for stdout; empty unless StageCommon::verbose > 0
};

// Reads common.input and, when `multires` is given, its LODBAKE_multires extension; `check`, when
// given, runs on the asset as part of loading (stages that use the images pass checkImages; the
// others keep images encoded and never load OpenImageIO), with ImageCheck::Header when
// common.inputImagesDecoded and ImageCheck::Decode otherwise. Passes the reader's warnings to
// common.warning. `seconds` gets the load time.
// \throw the errors of readGltf and of `check`.
Asset loadStageInput(const StageCommon& common, double& seconds, std::optional<Multires>* multires = nullptr,
                     void (*check)(Asset&, ImageCheck) = nullptr);

// Writes asset + multires to common.output (or common.outputBytes) with generator
// "lodbake TOOL 0.1.0"; returns seconds. \throw the errors of writeGltf.
double writeStageOutput(const StageCommon& common, const Asset& asset, const Multires* multires, const std::string& tool);

// Writes a JSON report atomically (pretty-printed with 2 spaces, keys sorted).
void writeReport(const std::string& path, const nlohmann::json& report);

// Appends printf-formatted text to `out` (statistics lines).
void appendf(std::string& out, const char* format, ...) __attribute__((format(printf, 2, 3)));

}  // namespace lodbake
