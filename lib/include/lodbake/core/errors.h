// The one error taxonomy of lodbake. Library code throws these; nothing below a tool's main
// prints or exits. The tools map them to the exit-code table of tools/common/cli.h.
//
//   Error kind      meaning
//   UsageError      bad command line (thrown by tools/ only)
//   IOError         file missing, unreadable or unwritable
//   InvalidInput    the file is read but is not valid glTF / holds invalid data
//   Unsupported     the input needs something lodbake does not support
//                   (an extensionsRequired entry, a feature), named in the message
//   Impossible      the input is valid but the operation cannot be done (say why)
//   SolverError     internal or numerical failure (Ceres did not converge, ...)
//   Cancelled       a progress callback returned false: the caller stopped the work (not a
//                   property of the input)
//
// Every message is one line and, when a file is involved, starts with the file path.
#pragma once

#include <stdexcept>
#include <string>

namespace lodbake {

enum class ErrorKind { Usage, IO, InvalidInput, Unsupported, Impossible, Solver, Cancelled };

class Error : public std::runtime_error {
public:
    Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
    ErrorKind kind() const { return kind_; }

private:
    ErrorKind kind_;
};

struct UsageError : Error {
    explicit UsageError(const std::string& m) : Error(ErrorKind::Usage, m) {}
};
struct IOError : Error {
    explicit IOError(const std::string& m) : Error(ErrorKind::IO, m) {}
};
struct InvalidInput : Error {
    explicit InvalidInput(const std::string& m) : Error(ErrorKind::InvalidInput, m) {}
};
struct Unsupported : Error {
    explicit Unsupported(const std::string& m) : Error(ErrorKind::Unsupported, m) {}
};
struct Impossible : Error {
    explicit Impossible(const std::string& m) : Error(ErrorKind::Impossible, m) {}
};
struct SolverError : Error {
    explicit SolverError(const std::string& m) : Error(ErrorKind::Solver, m) {}
};
struct Cancelled : Error {
    explicit Cancelled(const std::string& m) : Error(ErrorKind::Cancelled, m) {}
};

// The first line of a library's message, without surrounding blanks or a final period (messages
// stay one line).
inline std::string firstLine(std::string s) {
    while (!s.empty() && (s.front() == '\n' || s.front() == ' ')) s.erase(s.begin());
    size_t nl = s.find('\n');
    if (nl != std::string::npos) s.resize(nl);
    while (!s.empty() && (s.back() == '\r' || s.back() == ' ' || s.back() == '.')) s.pop_back();
    return s;
}

}  // namespace lodbake
