#include "policy/available_memory.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#if __has_include(<unistd.h>)
#include <unistd.h>
#endif

#include "tricell/neighbor_list.hpp"

namespace tricell {

namespace detail {

namespace {

// The limit written in a memory.max or memory.limit_in_bytes file; nullopt for a missing file,
// "max", or a number too large to be a real limit (version 1 writes its "none" as about 2^63
// rounded down to a page).
std::optional<std::uint64_t> read_limit(const std::string& path) {
    std::ifstream file(path);
    std::string text;
    if (!(file >> text) || text.empty() || text.find_first_not_of("0123456789") != text.npos ||
        text.size() > 19) {
        return std::nullopt;
    }
    const std::uint64_t bytes = std::stoull(text);
    if (bytes == 0 || bytes >= (std::uint64_t(1) << 62)) {
        return std::nullopt;
    }
    return bytes;
}

// "/a/b/c" -> {"/a/b/c", "/a/b", "/a", ""}: the group and its parents up to the root. A path
// that climbs out of the mount ("/../.."; a group outside a container's namespace) leaves the
// root alone.
std::vector<std::string> group_and_parents(std::string path) {
    std::vector<std::string> groups;
    if (path.find("..") != path.npos) {
        path.clear();
    }
    while (!path.empty() && path.back() == '/') {
        path.pop_back();
    }
    while (!path.empty()) {
        groups.push_back(path);
        path.erase(path.rfind('/') == path.npos ? 0 : path.rfind('/'));
    }
    groups.emplace_back();
    return groups;
}

} // namespace

std::optional<std::uint64_t> cgroup_memory_limit(const std::string& root,
                                                 const std::string& self_cgroup) {
    std::optional<std::uint64_t> limit;
    const auto take = [&](const std::string& file) {
        if (const auto bytes = read_limit(file)) {
            limit = limit ? std::min(*limit, *bytes) : *bytes;
        }
    };
    // Each line is "id:controllers:path": version 2 is "0::path", version 1's memory
    // controller "n:memory:path" (its list may name other controllers too).
    std::istringstream lines(self_cgroup);
    for (std::string line; std::getline(lines, line);) {
        const auto first = line.find(':');
        const auto second = first == line.npos ? line.npos : line.find(':', first + 1);
        if (second == line.npos) {
            continue;
        }
        const std::string controllers = "," + line.substr(first + 1, second - first - 1) + ",";
        const std::string path = line.substr(second + 1);
        const bool v2 = controllers == ",,";
        const bool v1 = controllers.find(",memory,") != controllers.npos;
        for (const std::string& group : group_and_parents(path)) {
            if (v2) {
                take(root + group + "/memory.max");
            } else if (v1) {
                take(root + "/memory" + group + "/memory.limit_in_bytes");
            }
        }
    }
    return limit;
}

std::uint64_t physical_memory() {
#if defined(_SC_PHYS_PAGES) && defined(_SC_PAGE_SIZE)
    const long pages = sysconf(_SC_PHYS_PAGES);
    const long page = sysconf(_SC_PAGE_SIZE);
    if (pages > 0 && page > 0) {
        return std::uint64_t(pages) * std::uint64_t(page);
    }
#endif
    return 0;
}

} // namespace detail

std::size_t default_max_bytes() {
    // Three quarters of the memory this process may use, read once: the rest is the caller's
    // arrays, the search's O(N) part and everything else running.
    static const std::size_t bytes = [] {
        std::uint64_t memory = detail::physical_memory();
        std::ifstream file("/proc/self/cgroup");
        const std::string self((std::istreambuf_iterator<char>(file)),
                               std::istreambuf_iterator<char>());
        if (const auto limit = detail::cgroup_memory_limit("/sys/fs/cgroup", self)) {
            memory = memory == 0 ? *limit : std::min(memory, *limit);
        }
        return std::size_t(double(memory) * 0.75);
    }();
    return bytes;
}

} // namespace tricell
