#pragma once
// A block of equally long, 64-byte aligned double columns: the unit of structure-of-arrays
// storage. Column k of a store with padded length P starts at data() + k * P.

#include <cstddef>
#include <utility>

#include "engine/aligned.hpp"

namespace ifsim {

class ColumnStore {
public:
    ColumnStore() = default;
    ColumnStore(int columns, std::size_t padded_length, double fill = 0.0)
        : cols_(columns), p_(padded_length),
          data_(static_cast<std::size_t>(columns) * padded_length, fill) {}

    int columns() const { return cols_; }
    std::size_t length() const { return p_; }
    double* col(int k) { return data_.data() + static_cast<std::size_t>(k) * p_; }
    const double* col(int k) const { return data_.data() + static_cast<std::size_t>(k) * p_; }
    void swap(ColumnStore& o) noexcept {
        std::swap(cols_, o.cols_);
        std::swap(p_, o.p_);
        data_.swap(o.data_);
    }

private:
    int cols_ = 0;
    std::size_t p_ = 0;
    aligned_vector data_;
};

} // namespace ifsim
