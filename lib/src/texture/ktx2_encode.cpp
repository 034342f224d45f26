// KTX2 through the basisu executable: write the source image into a private temporary folder,
// run the encoder there with an argument vector (posix_spawn, no shell; its chatter goes to a log
// file), read the .ktx2 back, remove the folder.

#include "lodbake/texture/ktx2.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "lodbake/core/errors.h"

extern char** environ;

namespace lodbake {
namespace {

namespace fs = std::filesystem;

bool executable(const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec) && access(p.c_str(), X_OK) == 0;
}

// A private folder (mode 0700) removed with everything in it when this goes out of scope.
struct TempDir {
    fs::path path;
    TempDir() {
        std::string pattern = (fs::temp_directory_path() / "lodbake-ktx2-XXXXXX").string();
        if (!mkdtemp(pattern.data())) throw IOError("encodeKtx2: cannot create a temporary folder in " + fs::temp_directory_path().string());
        path = pattern;
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
};

void writeBytes(const fs::path& p, const std::vector<uint8_t>& bytes) {
    std::ofstream f(p, std::ios::binary);
    f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!f) throw IOError("encodeKtx2: cannot write " + p.string());
}

std::string lastLine(const fs::path& log) {
    std::ifstream f(log);
    std::string line, last;
    while (std::getline(f, line))
        if (!line.empty()) last = line;
    return last;
}

// Runs argv[0] with stdout and stderr appended to `log`; returns its exit status (-1 = no start).
int run(const std::vector<std::string>& args, const fs::path& log) {
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) return -1;
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

std::string findBasisu() {
    if (const char* env = std::getenv("BASISU_PATH"); env && *env) return executable(env) ? std::string(env) : "";
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path ? path : "");
    for (std::string dir; std::getline(dirs, dir, ':');)
        if (!dir.empty() && executable(fs::path(dir) / "basisu")) return (fs::path(dir) / "basisu").string();
    return "";
}

Image encodeKtx2(const Image& source, const Ktx2Options& o) {
    if (o.encoder.empty() || !executable(o.encoder))
        throw IOError("encodeKtx2: the Basis Universal encoder 'basisu' is missing (" +
                      (o.encoder.empty() ? std::string("not found") : o.encoder) + ")");
    TempDir dir;
    const fs::path in = dir.path / (source.mimeType == "image/jpeg" ? "in.jpg" : "in.png");
    const fs::path out = dir.path / "out.ktx2", log = dir.path / "basisu.log";
    writeBytes(in, source.encoded);
    std::vector<std::string> args = {o.encoder, "-ktx2", "-no_multithreading", "-file", in.string(), "-output_file", out.string()};
    if (o.mipmaps) args.push_back("-mipmap");
    if (o.codec == Ktx2Codec::Uastc) {
        args.insert(args.end(), {"-uastc", "-uastc_level", std::to_string(o.uastcLevel)});
    } else {
        args.insert(args.end(), {"-q", std::to_string(o.etc1sQuality)});
    }
    if (o.normalMap) args.push_back("-normal_map");
    else if (!o.srgb) args.push_back("-linear");
    const int status = run(args, log);
    std::ifstream f(out, std::ios::binary);
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (status != 0 || bytes.empty())
        throw IOError("encodeKtx2: " + o.encoder + " failed on '" + source.name + "' (status " + std::to_string(status) +
                      "): " + lastLine(log));
    Image img = source;
    img.mimeType = "image/ktx2";
    img.encoded = std::move(bytes);
    return img;
}

}  // namespace lodbake
