// lodbake's batch mode: many inputs (files, or folders walked for .glb/.gltf) in one command, each
// baked by a child `lodbake` process with the same flags, at most `jobs` at a time. A file that
// fails does not stop the others; one summary report lists every file. Processes rather than
// threads, so one file's failure (or memory) never touches another's run, and each child's output
// is byte-identical to a single-file run with the same flags.
#pragma once

#include <string>
#include <vector>

namespace lodbake::batch {

struct BatchSettings {
    std::vector<std::string> inputs;     // files and folders, as given
    std::string outputDir;               // empty = each chain beside its input
    std::string report;                  // summary JSON path; empty = none
    std::vector<std::string> passOn;     // every other flag, passed on to each child as given
    int jobs = 1;                        // children at a time
    int threadsPerJob = 0;               // --threads for each child (0 = the child's default)
    std::string self;                    // the lodbake executable to run per file
    bool progress = false;               // a line per finished file on stderr
};

// A folder is walked recursively for .glb and .gltf files (sorted by path), leaving out lodbake's
// own outputs (*.lod.glb, *.lod.gltf); a file is taken as it is. \throw IOError (an input that does not
// exist, or no glTF file found at all).
std::vector<std::string> collectInputs(const std::vector<std::string>& inputs);

// Runs every input; prints each child's stderr lines (its warnings and error) after it ends, so
// lines of different files never interleave. Returns 0 when every file succeeded, else the largest
// exit code of a failed file.
int runBatch(const BatchSettings& settings);

}  // namespace lodbake::batch
