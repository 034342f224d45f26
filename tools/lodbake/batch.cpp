// lodbake's batch mode (batch.h): the inputs, one child process per file, the summary report.
#include "batch.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <cstring>
#include <thread>

#include <nlohmann/json.hpp>

#include "common/cli.h"
#include "lodbake/core/errors.h"
#include "lodbake/stages/stage.h"

extern char** environ;

namespace lodbake::batch {
namespace fs = std::filesystem;
namespace {

// One file of the batch: its path and where its chain goes, relative to the output folder
// (the file's path under the folder it was found in, without the extension).
struct Input {
    std::string path;
    fs::path relative;
};

bool isGltf(const fs::path& p) {
    std::string name = p.filename().string();
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    auto endsWith = [&](const std::string& e) { return name.size() >= e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0; };
    return (endsWith(".glb") || endsWith(".gltf")) && !endsWith(".lod.glb") && !endsWith(".lod.gltf");
}

std::vector<Input> collect(const std::vector<std::string>& inputs) {
    std::vector<Input> out;
    for (const std::string& in : inputs) {
        std::error_code ec;
        if (fs::is_directory(in, ec)) {
            std::vector<Input> found;
            for (auto it = fs::recursive_directory_iterator(in, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
                if (it->is_regular_file(ec) && isGltf(it->path()))
                    found.push_back({it->path().string(), fs::relative(it->path(), in, ec).replace_extension()});
            std::sort(found.begin(), found.end(), [](const Input& a, const Input& b) { return a.path < b.path; });
            out.insert(out.end(), found.begin(), found.end());
        } else if (fs::exists(in, ec)) {
            out.push_back({in, fs::path(in).filename().replace_extension()});
        } else {
            throw IOError(in + ": no such file or folder");
        }
    }
    if (out.empty()) throw IOError("no .glb or .gltf file among the inputs");
    return out;
}

std::string readText(const fs::path& p) {
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

// A running or finished child.
struct Job {
    Input input;
    std::string output;
    fs::path report, log;
    pid_t pid = -1;
    int exit = -1;
    std::chrono::steady_clock::time_point start;
    double seconds = 0;
};

// Starts `self` on one file; its stdout is discarded, its stderr goes to job.log.
void start(const BatchSettings& s, const std::vector<std::string>& passOn, Job& job) {
    std::vector<std::string> args = {s.self, "-i", job.input.path, "-o", job.output, "--report", job.report.string(), "--quiet"};
    args.insert(args.end(), passOn.begin(), passOn.end());
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 2, job.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    job.start = std::chrono::steady_clock::now();
    const int rc = posix_spawn(&job.pid, s.self.c_str(), &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) throw IOError(s.self + ": cannot start (" + std::string(std::strerror(rc)) + ")");
}

// The summary row of a finished job, from its exit status, stderr and report.
nlohmann::json row(const Job& job) {
    nlohmann::json r;
    r["input"] = job.input.path;
    r["exit"] = job.exit;
    r["seconds"] = job.seconds;
    std::vector<std::string> warnings;
    std::string error;
    std::istringstream log(readText(job.log));
    for (std::string line; std::getline(log, line);) {
        if (line.find(" error: ") != std::string::npos) error = line;
        else if (line.find(" warning: ") != std::string::npos) warnings.push_back(line);
    }
    r["warnings"] = warnings.size();
    if (job.exit != 0) {
        r["error"] = error.empty() ? "exited with code " + std::to_string(job.exit) : error;
        return r;
    }
    r["output"] = job.output;
    std::error_code ec;
    r["bytes"] = fs::file_size(job.output, ec);
    const nlohmann::json rep = nlohmann::json::parse(readText(job.report), nullptr, false);
    if (rep.is_discarded() || !rep.contains("stages") || rep["stages"].empty()) return r;
    const nlohmann::json& pack = rep["stages"].back();
    nlohmann::json triangles = nlohmann::json::array();
    double worst = 0;
    for (const auto& L : pack.value("levels", nlohmann::json::array())) {
        triangles.push_back(L.value("triangles", 0));
        if (L.contains("deviation")) worst = std::max(worst, L["deviation"].value("relHausdorff", 0.0));
    }
    r["levels"] = triangles.size();
    r["triangles"] = triangles;
    r["worstRelHausdorff"] = worst;
    return r;
}

}  // namespace

std::vector<std::string> collectInputs(const std::vector<std::string>& inputs) {
    std::vector<std::string> out;
    for (const Input& in : collect(inputs)) out.push_back(in.path);
    return out;
}

int runBatch(const BatchSettings& s) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<Input> inputs = collect(s.inputs);
    std::vector<std::string> passOn = s.passOn;
    const int jobs = std::max(1, s.jobs);
    // Each child gets an equal share of the cores unless --threads was given (output does not
    // depend on it).
    if (std::find(passOn.begin(), passOn.end(), "--threads") == passOn.end()) {
        const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
        passOn.insert(passOn.end(), {"--threads", std::to_string(std::max(1, cores / jobs))});
    }
    std::error_code ec;
    if (!s.outputDir.empty()) fs::create_directories(s.outputDir, ec);
    if (!s.outputDir.empty() && !fs::is_directory(s.outputDir, ec)) throw IOError(s.outputDir + ": cannot create the output folder");
    std::string tmpl = (fs::temp_directory_path() / "lodbake-batch-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw IOError("cannot create a temporary folder for the batch's reports");
    const fs::path tmp = tmpl;

    std::vector<Job> all(inputs.size());
    for (size_t i = 0; i < inputs.size(); ++i) {
        Job& j = all[i];
        j.input = inputs[i];
        const fs::path name = j.input.relative.string() + ".lod.glb";
        j.output = s.outputDir.empty() ? (fs::path(j.input.path).parent_path() / name.filename()).string()
                                       : (fs::path(s.outputDir) / name).string();
        if (!s.outputDir.empty()) fs::create_directories(fs::path(j.output).parent_path(), ec);
        j.report = tmp / (std::to_string(i) + ".json");
        j.log = tmp / (std::to_string(i) + ".log");
    }
    std::map<pid_t, size_t> running;
    size_t next = 0, finished = 0;
    while (finished < all.size()) {
        while (next < all.size() && running.size() < size_t(jobs)) {
            start(s, passOn, all[next]);
            running[all[next].pid] = next;
            ++next;
        }
        int status = 0;
        const pid_t pid = waitpid(-1, &status, 0);
        if (pid < 0) {
            if (errno == EINTR) continue;
            throw SolverError(std::string("waiting for a batch job failed: ") + std::strerror(errno));
        }
        auto it = running.find(pid);
        if (it == running.end()) continue;
        Job& j = all[it->second];
        running.erase(it);
        ++finished;
        j.exit = WIFEXITED(status) ? WEXITSTATUS(status) : cli::kInternal;
        j.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - j.start).count();
        // The child's own lines, together: its warnings, then its error if it failed.
        const std::string log = readText(j.log);
        std::fputs(log.c_str(), stderr);
        if (s.progress)
            std::fprintf(stderr, "lodbake: [%zu/%zu] %s: %s (%.1f s)\n", finished, all.size(), j.input.path.c_str(),
                         j.exit == 0 ? "done" : ("exit " + std::to_string(j.exit)).c_str(), j.seconds);
    }

    nlohmann::json files = nlohmann::json::array();
    int worstExit = 0, failed = 0;
    for (const Job& j : all) {
        files.push_back(row(j));
        if (j.exit != 0) ++failed;
        worstExit = std::max(worstExit, j.exit);
    }
    fs::remove_all(tmp, ec);
    if (!s.report.empty()) {
        nlohmann::json rep;
        rep["tool"] = "lodbake";
        rep["mode"] = "batch";
        rep["jobs"] = jobs;
        rep["files"] = files;
        rep["succeeded"] = int(all.size()) - failed;
        rep["failed"] = failed;
        rep["time"] = {{"total", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()}};
        writeReport(s.report, rep);
    }
    return worstExit;
}

}  // namespace lodbake::batch
