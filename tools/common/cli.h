// The CLI kit every lodbake tool uses (STYLE.md practice 9): option groups, the reporter, the
// exit-code table, progress on a terminal. The tools' work itself is in the stages
// (lodbake/stages/*.h); a tool's main parses flags into a stage's settings, validates them and
// runs the stage through runTool, which maps the errors of lodbake/core/errors.h to exit codes.
//
// Exit codes (DESIGN.md, "Command-line contract"), the one table of lodbake:
//   0 success
//   1 usage error (unknown flag, bad value, missing -i/-o)                      UsageError
//   2 unreadable or invalid input (missing file, malformed glTF, unsupported    IOError, InvalidInput,
//     required extension)                                                       Unsupported
//   3 the input is valid but the operation is impossible (the message says why) Impossible
//   4 internal or solver failure                                                SolverError, any other
// A Cancelled error (a progress callback returned false) never reaches a tool: their progress
// printers never cancel; were one to, it is no verdict on the input and takes 4.
#pragma once

#include <cstdio>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "lodbake/core/errors.h"
#include "lodbake/stages/stage.h"

namespace lodbake::cli {

enum ExitCode { kOk = 0, kUsage = 1, kBadInput = 2, kImpossible = 3, kInternal = 4 };

// The exit code of an error kind (the table above).
int exitCodeFor(ErrorKind kind);

// A minimal declarative flag parser. Unknown flags are fatal (UsageError).
class ArgParser {
public:
    ArgParser(std::string tool, std::string synopsis);
    // A flag taking a value: handler gets the value string and throws UsageError on bad input.
    void option(const std::string& names, const std::string& valueName, const std::string& help,
                std::function<void(const std::string&)> handler);
    // A flag without a value.
    void flag(const std::string& names, const std::string& help, std::function<void()> handler);
    // A heading in --help before the flags added next (tools with several stages' flags); `intro`,
    // when given, is a paragraph printed above the heading (a heading over several sections).
    void section(const std::string& title, const std::string& intro = "");
    // Lists these flags (any of their names) first in --help, in this order, under `title`; they
    // are left out where they were defined, and the other flags without a section follow under
    // "Other options". For tools with many flags, most of which few users need.
    void featured(const std::string& title, const std::vector<std::string>& names);
    // Replaces the help text of a flag already defined (by any of its names): a shared option group's
    // flag whose meaning or default differs in one tool. \throw std::logic_error for an unknown name.
    void describe(const std::string& name, const std::string& help);
    // Positional arguments (tools such as compare); if not set, positionals are usage errors.
    void positionals(const std::string& names, std::function<void(const std::string&)> handler);
    // Adds -i, -o, --report, -v/-vv, --threads bound to `s`, and -q/--quiet bound to `quiet`.
    void addCommon(StageCommon& s, bool& quiet, bool needsOutput = true);
    // Replaces the standard exit-code table at the end of --help (for tools whose codes differ).
    void exitCodes(std::string text) { exitCodes_ = std::move(text); }
    // Parses argv. Returns false when --help or --version was handled (exit 0).
    bool parse(int argc, char** argv);
    // The options parse() took, as arguments again (flag, then its value if it takes one), in the
    // order given, leaving out every option one of whose names is in `except` (and positionals):
    // what a tool passes on when it runs itself per input (lodbake's batch mode).
    std::vector<std::string> argumentsExcept(const std::vector<std::string>& except) const;
    std::string help() const;

private:
    struct Opt {
        std::vector<std::string> names;
        std::string valueName, help;
        std::function<void(const std::string&)> handler;
        bool takesValue;
        std::string section;  // heading printed before this flag; empty = none
        std::string sectionIntro;  // paragraph above that heading; empty = none
    };
    std::string pendingSection_, pendingIntro_;
    std::string featuredTitle_;
    std::vector<std::string> featured_;
    Opt* find(const std::string& name);
    const Opt* find(const std::string& name) const;
    void add(Opt opt);
    std::string tool_, synopsis_;
    std::vector<Opt> opts_;
    std::vector<std::pair<size_t, std::string>> parsed_;  // (index into opts_, value) of each option parsed
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

// A default value as help texts print it: "0.8", "0.005", "100000".
std::string number(double v);

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

// Validates -i/-o before any heavy work: input exists, output extension is .glb/.gltf (or any of
// `allowedExt`), output folder exists. Throws UsageError / IOError.
void checkPaths(const StageCommon& s, const std::vector<std::string>& allowedExt = {".glb", ".gltf"});

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

// Progress is drawn when stderr is a terminal and --quiet was not given.
bool progressEnabled(bool quiet);

// Prints "TOOL warning: message" on stderr.
void printWarning(const std::string& tool, const std::string& message);

// Runs a stage for `tool` with the progress printer (see progressEnabled) and the warning printer
// installed in settings.common, then prints the stage's statistics on stdout. Returns kOk; the
// stage's errors propagate to runTool.
template <class Settings, class Stage>
int runStage(const std::string& tool, Settings settings, bool quiet, Stage stage) {
    Progress progress(tool, progressEnabled(quiet));
    settings.common.progress = [&progress](double f) { return progress(f); };
    settings.common.warning = [&tool](const std::string& w) { printWarning(tool, w); };
    StageResult result = stage(settings);
    progress.done();
    std::fputs(result.statistics.c_str(), stdout);
    return kOk;
}

}  // namespace lodbake::cli
