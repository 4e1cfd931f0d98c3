// The MPI sweep (built with IFSIM_MPI). Messages: a worker asks for runs (REQUEST, once per
// slot), rank 0 answers with a run (WORK: a token, the run's folder and command line); a worker
// reports each ended run (DONE: token, exit code, signal, wall time, the run's summary.json
// text), which frees that slot; workers need no sweep of their own, so the same workers serve a
// calibration's runs;
// STOP ends a worker once rank 0 has every run back. Ranks poll (MPI_Iprobe) so that each can
// watch its child processes at the same time.

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <deque>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "io/cli/exit_codes.hpp"
#include "io/output/stop_signal.hpp"
#include "io/sweep/mpi_sweep.hpp"
#include "io/sweep/run_pool.hpp"
#include "io/sweep/sweep_coordinator.hpp"
#include "io/sweep/sweep_plan.hpp"

namespace ifsim::io {

namespace {

enum Tag : int { request_tag = 1, work_tag = 2, done_tag = 3, stop_tag = 4 };

// The fixed part of a DONE message, followed by the summary text.
struct DoneHead {
    std::uint64_t member;
    std::int32_t exit_code;
    std::int32_t signal;
    double wall_s;
};

class MpiSession {
public:
    MpiSession() {
        MPI_Init(nullptr, nullptr);
        MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &size_);
        MPI_Comm node;
        MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
        MPI_Comm_size(node, &node_size_);
        MPI_Comm_free(&node);
    }
    ~MpiSession() { MPI_Finalize(); }
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;
    int rank() const { return rank_; }
    int size() const { return size_; }
    int node_size() const { return node_size_; }

private:
    int rank_ = 0, size_ = 1, node_size_ = 1;
};

// Rank 0's view of the other ranks.
class MpiWorkers final : public RemoteWorkers {
public:
    MpiWorkers(int size, int jobs_per_rank) : size_(size), jobs_(jobs_per_rank) {}

    bool has_free_slot() override {
        int flag = 1;
        while (flag) {
            MPI_Status st;
            MPI_Iprobe(MPI_ANY_SOURCE, request_tag, MPI_COMM_WORLD, &flag, &st);
            if (flag) {
                int slots = 0;
                MPI_Recv(&slots, 1, MPI_INT, st.MPI_SOURCE, request_tag, MPI_COMM_WORLD,
                         MPI_STATUS_IGNORE);
                free_.insert(free_.end(), static_cast<std::size_t>(slots), st.MPI_SOURCE);
            }
        }
        return !free_.empty();
    }

    void start(std::size_t token, const std::vector<std::string>& argv,
               const std::filesystem::path& run_dir) override {
        const int rank = free_.front();
        free_.pop_front();
        const std::uint64_t t = token;
        std::string message(reinterpret_cast<const char*>(&t), sizeof t);
        message += run_dir.string();
        for (const std::string& a : argv) {
            message += '\0';
            message += a;
        }
        MPI_Send(message.data(), static_cast<int>(message.size()), MPI_BYTE, rank, work_tag,
                 MPI_COMM_WORLD);
        ++outstanding_;
    }

    std::optional<RemoteEnd> poll() override {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, done_tag, MPI_COMM_WORLD, &flag, &st);
        if (!flag) {
            return std::nullopt;
        }
        int bytes = 0;
        MPI_Get_count(&st, MPI_BYTE, &bytes);
        std::vector<char> buffer(static_cast<std::size_t>(bytes));
        MPI_Recv(buffer.data(), bytes, MPI_BYTE, st.MPI_SOURCE, done_tag, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE);
        DoneHead head;
        std::memcpy(&head, buffer.data(), sizeof head);
        RemoteEnd end;
        end.member = head.member;
        end.end.exit_code = head.exit_code;
        end.end.signal = head.signal;
        end.wall_s = head.wall_s;
        end.summary_text.assign(buffer.begin() + sizeof head, buffer.end());
        end.rank = st.MPI_SOURCE;
        --outstanding_;
        free_.push_back(st.MPI_SOURCE); // the slot that ran it is free again
        return end;
    }

    std::size_t outstanding() const override { return outstanding_; }

    void finish() override {
        if (finished_) {
            return;
        }
        finished_ = true;
        for (int r = 1; r < size_; ++r) {
            MPI_Send(nullptr, 0, MPI_BYTE, r, stop_tag, MPI_COMM_WORLD);
        }
    }

    int slots() const override { return (size_ - 1) * jobs_; }

private:
    int size_;
    int jobs_;
    std::deque<int> free_; // one entry per free slot, by rank
    std::size_t outstanding_ = 0;
    bool finished_ = false;
};

void send_done(const RunPool::Ended& end, const std::string& summary) {
    const DoneHead head{end.member, end.end.exit_code, end.end.signal, end.wall_s};
    std::vector<char> buffer(sizeof head + summary.size());
    std::memcpy(buffer.data(), &head, sizeof head);
    std::memcpy(buffer.data() + sizeof head, summary.data(), summary.size());
    MPI_Send(buffer.data(), static_cast<int>(buffer.size()), MPI_BYTE, 0, done_tag, MPI_COMM_WORLD);
}

struct Work {
    std::uint64_t token = 0;
    std::filesystem::path run_dir;
    std::vector<std::string> argv;
};

Work receive_work(const MPI_Status& st) {
    int bytes = 0;
    MPI_Get_count(&st, MPI_BYTE, &bytes);
    std::string message(static_cast<std::size_t>(bytes), '\0');
    MPI_Recv(message.data(), bytes, MPI_BYTE, 0, work_tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    Work w;
    std::memcpy(&w.token, message.data(), sizeof w.token);
    std::vector<std::string> parts(1);
    for (std::size_t i = sizeof w.token; i < message.size(); ++i) {
        if (message[i] == '\0') {
            parts.emplace_back();
        } else {
            parts.back() += message[i];
        }
    }
    w.run_dir = parts.front();
    w.argv.assign(parts.begin() + 1, parts.end());
    return w;
}

std::string file_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return in ? text.str() : std::string();
}

} // namespace

namespace {

// A rank other than 0: runs what it is given until STOP.
int serve_runs(int local_jobs) {
    const StopSignals signals;
    RunPool pool(local_jobs);
    std::map<std::size_t, std::filesystem::path> dirs; // token -> run folder
    MPI_Send(&local_jobs, 1, MPI_INT, 0, request_tag, MPI_COMM_WORLD);
    bool stop = false, stopping = false;
    while (!stop || !pool.empty()) {
        bool busy = false;
        if (!stopping && stop_signal() != 0) {
            stopping = true;
            pool.stop_all();
        }
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
        if (flag && st.MPI_TAG == work_tag) {
            const Work w = receive_work(st);
            if (stopping) { // stopped before it could start: reported as not run
                send_done(RunPool::Ended{w.token, ProcessEnd{0, -1, -1}, 0.0}, "");
                continue;
            }
            try {
                std::filesystem::create_directories(w.run_dir);
                pool.start(w.token, w.argv, w.run_dir / "run.log");
                dirs[w.token] = w.run_dir;
            } catch (const std::exception& e) {
                // Reported as a run that left no summary; its log may not exist, so say it here.
                fmt::print(stderr, "ifsim sweep: {}\n", e.what());
                send_done(RunPool::Ended{w.token, ProcessEnd{0, 127, 0}, 0.0}, "");
            }
            busy = true;
        } else if (flag && st.MPI_TAG == stop_tag) {
            MPI_Recv(nullptr, 0, MPI_BYTE, 0, stop_tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            stop = true;
        }
        if (const auto end = pool.poll()) {
            send_done(*end, file_text(dirs[end->member] / "summary.json"));
            dirs.erase(end->member);
            busy = true;
        }
        if (!busy) {
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }
    return stopping ? interrupted_exit_code(stop_signal()) : exit_code::ok;
}

} // namespace

int run_on_mpi_ranks(const SweepOptions& opt,
                     const std::function<int(const SweepLayout&, RemoteWorkers&)>& coordinate) {
    const MpiSession mpi;
    // Every rank: the same layout. Jobs per rank (default 1), the node's cores shared out.
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    SweepLayout layout;
    layout.local_jobs = opt.jobs > 0 ? opt.jobs : 1;
    layout.threads = opt.threads_per_run > 0
                         ? opt.threads_per_run
                         : std::max(1, cores / (mpi.node_size() * layout.local_jobs));
    layout.ranks = mpi.size();
    if (mpi.rank() != 0) {
        return serve_runs(layout.local_jobs);
    }
    MpiWorkers workers(mpi.size(), layout.local_jobs);
    int code = exit_code::io_error;
    try {
        code = coordinate(layout, workers);
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim: error: {}\n", e.what());
    }
    // Every run handed out is reported before STOP (a report sent after rank 0 finalised would
    // never be received and could block its worker).
    while (workers.outstanding() > 0) {
        if (!workers.poll()) {
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }
    workers.finish(); // the workers end whatever rank 0 ended with
    return code;
}

} // namespace ifsim::io
