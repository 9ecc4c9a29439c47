// epoch_bench: the C++ side of the epoch benchmark (benchmarks/epoch/README.md). Reads the
// epoch file written by make_epochs.py and times, for each epoch, one compute_neighbors() call
// per structure (into one reused list) and one compute_neighbors_batch() call over all of them,
// full lists storing i, j, S, d. The ways are interleaved round by round and each reports its
// median; before timing, every structure's slice of the batch is checked equal, array for array,
// to its own call. Not a test: timings live here.
//
//   epoch_bench FILE [--ways loop,batch] [--threads 1,2] [--repeat K] [--epochs a,b]
//
// Prints lines for run_epochs.py to read: "epoch NAME structures B atoms N pairs P",
// "time NAME WAY THREADS SECONDS", or "error NAME MESSAGE" when an epoch cannot be computed.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <tricell/batch.hpp>
#include <tricell/neighbor_list.hpp>

namespace {

using Clock = std::chrono::steady_clock;

// One epoch of the file: the concatenated batch format (epoch_file.py has the layout).
struct Epoch {
    std::string name;
    double cutoff = 0;
    std::vector<std::int64_t> ptr;
    std::vector<double> cells; // 9 per structure, rows are lattice vectors
    std::vector<std::uint8_t> pbc;
    std::vector<double> positions;
    std::size_t count() const { return ptr.size() - 1; }
};

template <class T> void read_into(std::ifstream& in, T* data, std::size_t count) {
    in.read(reinterpret_cast<char*>(data), std::streamsize(count * sizeof(T)));
    if (!in) {
        throw std::runtime_error("the epoch file ends too early");
    }
}

template <class T> T read_value(std::ifstream& in) {
    T value{};
    read_into(in, &value, 1);
    return value;
}

std::vector<Epoch> read_epochs(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw std::runtime_error("cannot open " + path + " (make_epochs.py writes it)");
    }
    const std::string magic = "TRICELL-EPOCHS-1";
    std::string head(magic.size(), '\0');
    read_into(in, &head[0], head.size());
    if (head != magic) {
        throw std::runtime_error(path + " is not an epoch file");
    }
    std::vector<Epoch> epochs(read_value<std::uint32_t>(in));
    for (Epoch& e : epochs) {
        e.name.resize(read_value<std::uint32_t>(in));
        read_into(in, &e.name[0], e.name.size());
        e.cutoff = read_value<double>(in);
        const auto structures = read_value<std::uint64_t>(in);
        const auto atoms = read_value<std::uint64_t>(in);
        e.ptr.resize(structures + 1);
        e.cells.resize(9 * structures);
        e.pbc.resize(3 * structures);
        e.positions.resize(3 * atoms);
        read_into(in, e.ptr.data(), e.ptr.size());
        read_into(in, e.cells.data(), e.cells.size());
        read_into(in, e.pbc.data(), e.pbc.size());
        read_into(in, e.positions.data(), e.positions.size());
    }
    return epochs;
}

std::vector<tricell::BatchStructure> structures_of(const Epoch& e) {
    std::vector<tricell::BatchStructure> out;
    for (std::size_t s = 0; s < e.count(); ++s) {
        Eigen::Matrix3d rows;
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) {
                rows(r, c) = e.cells[9 * s + std::size_t(3 * r + c)];
            }
        }
        tricell::Periodicity pbc;
        for (std::size_t a = 0; a < 3; ++a) {
            pbc.axes[a] = e.pbc[3 * s + a] != 0;
        }
        const auto begin = std::size_t(e.ptr[s]);
        out.push_back(
            tricell::BatchStructure{tricell::Box::from_rows(rows, pbc),
                                    tricell::PointsView(e.positions.data() + 3 * begin,
                                                        std::size_t(e.ptr[s + 1]) - begin)});
    }
    return out;
}

// Whether `list` equals pairs [begin, begin + list.size()) of `batch`, array for array.
bool same_slice(const tricell::NeighborList& list, const tricell::BatchList& batch,
                std::size_t begin) {
    const std::size_t n = list.size();
    const auto equal = [&](const auto& mine, const auto& theirs, std::size_t width) {
        return n == 0 || std::memcmp(mine.data(), theirs.data() + width * begin,
                                     width * n * sizeof(mine[0])) == 0;
    };
    return equal(list.i(), batch.i(), 1) && equal(list.j(), batch.j(), 1) &&
           equal(list.shifts(), batch.shifts(), 3) && equal(list.distances(), batch.distances(), 1);
}

std::vector<std::string> split(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');) {
        out.push_back(item);
    }
    return out;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: epoch_bench FILE [--ways loop,batch] [--threads 1,2] "
                             "[--repeat K] [--epochs NAME,...]\n");
        return 2;
    }
    std::vector<std::string> ways{"loop", "batch"}, only;
    std::vector<int> thread_counts{1};
    int repeat = 5;
    for (int a = 2; a + 1 < argc; a += 2) {
        const std::string arg = argv[a], value = argv[a + 1];
        if (arg == "--ways") {
            ways = split(value);
        } else if (arg == "--threads") {
            thread_counts.clear();
            for (const std::string& t : split(value)) {
                thread_counts.push_back(std::atoi(t.c_str()));
            }
        } else if (arg == "--repeat") {
            repeat = std::max(1, std::atoi(value.c_str()));
        } else if (arg == "--epochs") {
            only = split(value);
        } else {
            std::fprintf(stderr, "epoch_bench: unknown option %s\n", arg.c_str());
            return 2;
        }
    }

    std::vector<Epoch> epochs;
    try {
        epochs = read_epochs(argv[1]);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "epoch_bench: %s\n", e.what());
        return 1;
    }
    int status = 0;
    for (const Epoch& e : epochs) {
        if (!only.empty() && std::find(only.begin(), only.end(), e.name) == only.end()) {
            continue;
        }
        tricell::NeighborOptions options;
        options.cutoff = e.cutoff;
        tricell::NeighborList list;
        tricell::BatchList batch;
        std::vector<tricell::BatchStructure> structures;
        try {
            structures = structures_of(e);
            compute_neighbors_batch(structures, options, batch);
            for (std::size_t s = 0; s < structures.size(); ++s) {
                tricell::compute_neighbors(structures[s].box, structures[s].positions, options,
                                           list);
                if (list.size() != batch.pair_offsets()[s + 1] - batch.pair_offsets()[s] ||
                    !same_slice(list, batch, batch.pair_offsets()[s])) {
                    std::printf("error %s structure %zu: the batch's list differs from its own "
                                "call's\n",
                                e.name.c_str(), s);
                    status = 1;
                    break;
                }
            }
        } catch (const std::exception& error) {
            std::printf("error %s %s\n", e.name.c_str(), error.what());
            continue;
        }
        std::printf("epoch %s structures %zu atoms %zu pairs %zu\n", e.name.c_str(), e.count(),
                    e.positions.size() / 3, batch.size());

        // Interleaved rounds: every way once per round, after one warm-up round.
        std::map<std::pair<std::string, int>, std::vector<double>> seconds;
        for (int round = 0; round <= repeat; ++round) {
            for (const int threads : thread_counts) {
                options.threads = threads;
                for (const std::string& way : ways) {
                    const auto start = Clock::now();
                    if (way == "loop") {
                        for (const tricell::BatchStructure& s : structures) {
                            tricell::compute_neighbors(s.box, s.positions, options, list);
                        }
                    } else if (way == "batch") {
                        compute_neighbors_batch(structures, options, batch);
                    } else {
                        std::fprintf(stderr, "epoch_bench: unknown way %s\n", way.c_str());
                        return 2;
                    }
                    if (round > 0) {
                        seconds[{way, threads}].push_back(
                            std::chrono::duration<double>(Clock::now() - start).count());
                    }
                }
            }
        }
        for (auto& [key, times] : seconds) {
            std::sort(times.begin(), times.end());
            std::printf("time %s %s %d %.6g\n", e.name.c_str(), key.first.c_str(), key.second,
                        times[times.size() / 2]);
        }
        std::fflush(stdout);
    }
    return status;
}
