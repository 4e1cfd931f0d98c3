#include "io/sweep/child_process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

extern char** environ;

namespace ifsim::io {

namespace fs = std::filesystem;

fs::path own_executable() {
    std::error_code ec;
    const fs::path p = fs::read_symlink("/proc/self/exe", ec);
    if (ec) {
        throw std::runtime_error(
            fmt::format("cannot find the ifsim executable (/proc/self/exe): {}", ec.message()));
    }
    return p;
}

pid_t start_process(const std::vector<std::string>& argv, const fs::path& log) {
    std::vector<char*> args;
    for (const std::string& a : argv) {
        args.push_back(const_cast<char*>(a.c_str()));
    }
    args.push_back(nullptr);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        throw std::runtime_error(
            fmt::format("cannot write {}: {}", log.string(), std::strerror(errno)));
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fd, STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, fd, STDERR_FILENO);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    // Its own process group: a Ctrl-C at the terminal or a kill of the sweep's group reaches
    // the sweep alone, which passes the stop on once (RunPool::stop_all).
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attributes, 0);
    pid_t pid = 0;
    const int rc =
        posix_spawn(&pid, argv.front().c_str(), &actions, &attributes, args.data(), environ);
    posix_spawnattr_destroy(&attributes);
    posix_spawn_file_actions_destroy(&actions);
    ::close(fd);
    if (rc != 0) {
        throw std::runtime_error(
            fmt::format("cannot start {}: {}", argv.front(), std::strerror(rc)));
    }
    return pid;
}

void reap_own_children() {
    ::signal(SIGCHLD, SIG_DFL); // inherited SIG_IGN would reap them before waitpid sees them
}

std::optional<ProcessEnd> child_ended(pid_t pid) {
    int status = 0;
    const pid_t got = ::waitpid(pid, &status, WNOHANG);
    if (got == -1 && errno == ECHILD) {
        return ProcessEnd{pid, -1, 0}; // gone without a status: counted as ended
    }
    if (got != pid) {
        return std::nullopt;
    }
    ProcessEnd end;
    end.pid = pid;
    if (WIFEXITED(status)) {
        end.exit_code = WEXITSTATUS(status);
    } else if (WIFSIGNALED(status)) {
        end.signal = WTERMSIG(status);
    }
    return end;
}

} // namespace ifsim::io
