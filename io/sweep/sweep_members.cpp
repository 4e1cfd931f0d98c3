#include "io/sweep/sweep_members.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace ifsim::io {

namespace {

std::string file_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw std::runtime_error(fmt::format("cannot read the scene file {}", path.string()));
    }
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

class Fnv1a {
public:
    void add(std::string_view bytes) {
        for (const char c : bytes) {
            hash_ ^= static_cast<unsigned char>(c);
            hash_ *= 0x100000001b3ULL;
        }
    }
    // With a final mix (splitmix64's), so runs that differ in one digit get ids that differ
    // at a glance.
    std::uint64_t value() const {
        std::uint64_t z = hash_;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }

private:
    std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

} // namespace

std::string run_id(const std::string& scene_text, const std::vector<std::string>& sets) {
    // Sorted: the order keys stand in the sweep file does not make another run.
    std::vector<std::string> sorted = sets;
    std::sort(sorted.begin(), sorted.end());
    Fnv1a h;
    h.add(scene_text);
    for (const std::string& s : sorted) {
        h.add(std::string_view("\0--set ", 7)); // a separator no scene text or key holds
        h.add(s);
    }
    return fmt::format("{:016x}", h.value());
}

std::vector<std::string> swept_keys(const SweepFile& sweep) {
    std::vector<std::string> keys;
    for (const SweepAxis& a : sweep.grid) {
        keys.push_back(a.key);
    }
    for (const SweepAxis& a : sweep.zip) {
        keys.push_back(a.key);
    }
    return keys;
}

std::vector<SweepMember> expand_sweep(const SweepFile& sweep) {
    std::vector<SweepMember> members;
    const std::size_t zip_length = sweep.zip.empty() ? 1 : sweep.zip.front().values.size();
    std::size_t grid_size = 1;
    for (const SweepAxis& a : sweep.grid) {
        grid_size *= a.values.size();
    }
    for (std::size_t s = 0; s < sweep.scenes.size(); ++s) {
        const std::string text = file_text(sweep.paths[s]);
        for (std::size_t g = 0; g < grid_size; ++g) {
            // Mixed-radix digits of g, the last grid key the fastest.
            std::vector<std::size_t> digit(sweep.grid.size());
            std::size_t rest = g;
            for (std::size_t k = sweep.grid.size(); k-- > 0;) {
                digit[k] = rest % sweep.grid[k].values.size();
                rest /= sweep.grid[k].values.size();
            }
            for (std::size_t z = 0; z < zip_length; ++z) {
                SweepMember m;
                m.index = members.size() + 1;
                m.scene = s;
                m.sets = sweep.fixed;
                for (std::size_t k = 0; k < sweep.grid.size(); ++k) {
                    const SweepAxis& a = sweep.grid[k];
                    m.sets.push_back(a.key + "=" + a.values[digit[k]]);
                    m.shown.push_back(a.display[digit[k]]);
                }
                for (const SweepAxis& a : sweep.zip) {
                    m.sets.push_back(a.key + "=" + a.values[z]);
                    m.shown.push_back(a.display[z]);
                }
                m.id = run_id(text, m.sets);
                members.push_back(std::move(m));
            }
        }
    }
    return members;
}

} // namespace ifsim::io
