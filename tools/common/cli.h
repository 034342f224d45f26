// The CLI kit every lodbake tool uses (STYLE.md practice 9): option groups, the reporter,
// exit codes, JSON reports, progress on a terminal.
//
// Exit codes (DESIGN.md, "Command-line contract"):
//   0 success
//   1 usage error (unknown flag, bad value, missing -i/-o)
//   2 unreadable or invalid input (missing file, malformed glTF, unsupported required extension)
//   3 the input is valid but the operation is impossible (the message says why)
//   4 internal or solver failure
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"

namespace lodbake::cli {

enum ExitCode { kOk = 0, kUsage = 1, kBadInput = 2, kImpossible = 3, kInternal = 4 };

// Flags every tool shares.
struct CommonSettings {
    std::string input;   // -i
    std::string output;  // -o
    std::string report;  // --report FILE.json
    int verbose = 0;     // -v (stats on stdout), -vv
    int threads = 0;     // --threads N; 0 = all cores
    bool quiet = false;  // --quiet: no progress even on a terminal
};

// A minimal declarative flag parser. Unknown flags are fatal (UsageError).
class ArgParser {
public:
    ArgParser(std::string tool, std::string synopsis);
    // A flag taking a value: handler gets the value string and throws UsageError on bad input.
    void option(const std::string& names, const std::string& valueName, const std::string& help,
                std::function<void(const std::string&)> handler);
    // A flag without a value.
    void flag(const std::string& names, const std::string& help, std::function<void()> handler);
    // Positional arguments (tools such as compare); if not set, positionals are usage errors.
    void positionals(const std::string& names, std::function<void(const std::string&)> handler);
    // Adds -i, -o, --report, -v/-vv, --threads, --quiet bound to `s`.
    void addCommon(CommonSettings& s, bool needsOutput = true);
    // Replaces the standard exit-code table at the end of --help (for tools whose codes differ).
    void exitCodes(std::string text) { exitCodes_ = std::move(text); }
    // Parses argv. Returns false when --help or --version was handled (exit 0).
    bool parse(int argc, char** argv);
    std::string help() const;

private:
    struct Opt {
        std::vector<std::string> names;
        std::string valueName, help;
        std::function<void(const std::string&)> handler;
        bool takesValue;
    };
    std::string tool_, synopsis_;
    std::vector<Opt> opts_;
    std::function<void(const std::string&)> positional_;
    std::string positionalNames_;
    std::string exitCodes_ =
        "Exit codes: 0 success, 1 usage error, 2 unreadable or invalid input,\n"
        "            3 valid input but the operation is impossible, 4 internal or solver failure.\n";
};

// Value parsers used by option handlers; they throw UsageError naming the flag.
double parseDouble(const std::string& flag, const std::string& v);
int parseInt(const std::string& flag, const std::string& v);
std::vector<double> parseDoubleList(const std::string& flag, const std::string& v);
std::vector<double> parseVec3(const std::string& flag, const std::string& v);

// Runs `body` inside the single try/catch that maps lodbake errors to exit codes and prints
// "TOOL error: message" (one line) on stderr. Usage errors add "See 'TOOL --help'.".
int runTool(const std::string& tool, const std::function<int()>& body);

// A tool's whole main: parse the arguments (parse sets proceed = false after --help/--version),
// then run, inside runTool.
template <class Settings, class RunFn>
int runMain(const std::string& tool, int argc, char** argv, Settings (*parse)(int, char**, bool&), RunFn run) {
    return runTool(tool, [&] {
        bool proceed = true;
        Settings s = parse(argc, argv, proceed);
        return proceed ? run(s) : 0;
    });
}

// Reads the tool's input (-i) and, when `multires` is given, its LODBAKE_multires extension;
// `check`, when given, runs on the asset as part of loading (tools that use the images pass
// lodbake::checkImages here; the others keep images encoded and never load OpenImageIO); prints
// the reader's warnings on stderr ("TOOL warning: ..."); `seconds` gets the load time.
Asset loadInput(const std::string& tool, const CommonSettings& s, double& seconds,
                std::optional<Multires>* multires = nullptr, void (*check)(Asset&) = nullptr);

// Seconds of wall time since t0 (the tools' per-stage report times).
inline double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Validates -i/-o before any heavy work: input exists, output extension is .glb/.gltf (or any of
// `allowedExt`), output folder exists. Throws UsageError / IOError.
void checkPaths(const CommonSettings& s, const std::vector<std::string>& allowedExt = {".glb", ".gltf"});

// Writes a JSON report atomically (pretty-printed, keys sorted, deterministic).
void writeReport(const std::string& path, const nlohmann::json& report);

// Progress printer: draws on stderr only when stderr is a terminal and !quiet.
class Progress {
public:
    Progress(std::string stage, bool enabled);
    ~Progress();
    bool operator()(double fraction);  // returns true (never cancels)
    void done();

private:
    std::string stage_;
    bool enabled_;
    int last_ = -1;
};
bool progressEnabled(const CommonSettings& s);

// Number of threads to use for `--threads N` (0 -> hardware concurrency).
int resolveThreads(int requested);

}  // namespace lodbake::cli
