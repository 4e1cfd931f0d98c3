#pragma once
// Aitken's dynamic relaxation of a fixed-point iteration x <- G(x) (Irons & Tuck 1969, in the
// vector form of Kuettler & Wall 2008, Comput Mech 43): with the residual r_k = G(x_k) - x_k,
//   omega_k = -omega_{k-1} r_{k-1}.(r_k - r_{k-1}) / |r_k - r_{k-1}|^2,  x_{k+1} = x_k + omega_k
//   r_k,
// and omega_0 = 1 (the plain step). For a map that contracts by a factor c along its slowest
// direction omega tends to 1/(1 - c): a gather of the novel interface's in-plane targets that
// shrinks by c = 0.8 per round (the §6 Sanisand runs, docs/large-scale-test.md) then needs a
// few rounds instead of ten.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace ifsim::fem {

class AitkenRelaxation {
public:
    // Bounds of omega: a nearly parallel pair of residuals must not throw the iterate far.
    static constexpr double min_factor = 0.1;
    static constexpr double max_factor = 10.0;

    // Forget the history: the next step is the plain one.
    void reset() {
        previous_.clear();
        omega_ = 1.0;
    }

    // The factor for the residual r (of the same length and meaning as the last one, else the
    // history is dropped). Stores r for the next call.
    double factor(const std::vector<double>& r) {
        if (previous_.size() == r.size() && !previous_.empty()) {
            double num = 0.0, den = 0.0;
            for (std::size_t i = 0; i < r.size(); ++i) {
                const double d = r[i] - previous_[i];
                num += previous_[i] * d;
                den += d * d;
            }
            if (den > 0.0) {
                omega_ = std::clamp(-omega_ * num / den, min_factor, max_factor);
            }
        } else {
            omega_ = 1.0;
        }
        previous_ = r;
        return omega_;
    }

    double last_factor() const { return omega_; }

private:
    std::vector<double> previous_;
    double omega_ = 1.0;
};

} // namespace ifsim::fem
