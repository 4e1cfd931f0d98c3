#pragma once
// Runs of a sweep as child processes (`ifsim run ...`): a run that crashes or is killed takes
// only itself down, and each run has its own thread limit and signal handling. Each child is
// the leader of its own process group.

#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace ifsim::io {

// The path of the running executable (/proc/self/exe).
std::filesystem::path own_executable();

// Starts argv[0] with the arguments argv[1...], its stdout and stderr written to `log`
// (created or truncated). Throws std::runtime_error naming the program or the log.
pid_t start_process(const std::vector<std::string>& argv, const std::filesystem::path& log);

struct ProcessEnd {
    pid_t pid = 0;
    int exit_code = -1; // when it exited
    int signal = 0;     // when a signal ended it
};

// Lets waitpid see our children's ends (SIGCHLD to its default; an inherited SIG_IGN would
// reap them unseen). Called before the first run starts.
void reap_own_children();

// How child `pid` ended, if it has (does not block; reaps it).
std::optional<ProcessEnd> child_ended(pid_t pid);

} // namespace ifsim::io
