#include "io/cli/thread_limit.hpp"

#include <tbb/info.h>

namespace ifsim::io {

ThreadLimit::ThreadLimit(int requested)
    : threads_(requested > 0 ? requested : tbb::info::default_concurrency()),
      control_(std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                     static_cast<std::size_t>(threads_))) {}

} // namespace ifsim::io
