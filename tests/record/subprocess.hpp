// A child process for tests: argv, stdout captured through a pipe (read the first line, e.g. the
// server's endpoints), stderr inherited; SIGTERM and reaped on destruction.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <sys/types.h>
#include <vector>

namespace polycut::record::test {

class Subprocess {
public:
    /// Starts argv[0] (a path) with the arguments. Throws std::runtime_error if it cannot.
    explicit Subprocess(const std::vector<std::string>& argv);
    ~Subprocess();
    Subprocess(const Subprocess&) = delete;
    Subprocess& operator=(const Subprocess&) = delete;

    /// The next line of the child's stdout, or nullopt on EOF or timeout.
    std::optional<std::string> read_line(std::chrono::milliseconds timeout);
    /// Sends SIGTERM and waits; returns the exit status (as from waitpid), -1 if already reaped.
    int terminate();
    /// Waits for the child to exit by itself; returns its exit code (-1 if killed by a signal).
    int wait();

private:
    pid_t m_pid = -1;
    int m_stdout = -1;
    std::string m_buffer;
};

/// Runs a command to completion; returns (exit code, stdout). -1 if killed by a signal.
std::pair<int, std::string> run_command(const std::vector<std::string>& argv);

} // namespace polycut::record::test
