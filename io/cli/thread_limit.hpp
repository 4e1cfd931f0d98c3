#pragma once
// --threads N: the number of TBB worker threads for the lifetime of this object
// (0 = all cores of the machine).

#include <memory>

#include <tbb/global_control.h>

namespace ifsim::io {

class ThreadLimit {
public:
    explicit ThreadLimit(int requested);
    int threads() const { return threads_; }

private:
    int threads_;
    std::unique_ptr<tbb::global_control> control_;
};

} // namespace ifsim::io
