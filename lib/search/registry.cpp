#include "search/registry.hpp"

#include <string>

#include "tricell/error.hpp"

namespace tricell {

namespace detail {
std::unique_ptr<Backend> make_dense_backend();
std::unique_ptr<Backend> make_linked_backend();
std::unique_ptr<Backend> make_hash_backend();
std::unique_ptr<Backend> make_octree_backend();
std::unique_ptr<Backend> make_direct_backend();

namespace {
// The one list of backends.
constexpr BackendEntry table[] = {
    {SearchBackend::automatic, "auto", nullptr},
    {SearchBackend::dense, "dense", make_dense_backend},
    {SearchBackend::linked, "linked", make_linked_backend},
    {SearchBackend::hash, "hash", make_hash_backend},
    {SearchBackend::octree, "octree", make_octree_backend},
    {SearchBackend::direct, "direct", make_direct_backend},
};
constexpr std::size_t table_size = sizeof(table) / sizeof(table[0]);
} // namespace

const BackendEntry* backend_table(std::size_t& count) {
    count = table_size;
    return table;
}

const BackendEntry* find_backend(SearchBackend backend) {
    for (const BackendEntry& e : table) {
        if (e.backend == backend) {
            return &e;
        }
    }
    return nullptr;
}

std::unique_ptr<Backend> make_backend(SearchBackend backend) {
    const BackendEntry* e = find_backend(backend);
    if (e == nullptr || e->make == nullptr) {
        fail<InvalidArgument>("no search structure for backend ", static_cast<int>(backend));
    }
    return e->make();
}

Backend& BackendPool::get(SearchBackend backend) {
    const auto slot = static_cast<std::size_t>(backend);
    static_assert(table_size <= slots, "BackendPool has a slot per backend");
    if (slot >= slots) {
        fail<InvalidArgument>("no search structure for backend ", static_cast<int>(backend));
    }
    if (!pool_[slot]) {
        pool_[slot] = make_backend(backend);
    }
    return *pool_[slot];
}

} // namespace detail

const std::vector<SearchBackend>& search_backends() {
    static const std::vector<SearchBackend> all = [] {
        std::vector<SearchBackend> v;
        for (const detail::BackendEntry& e : detail::table) {
            v.push_back(e.backend);
        }
        return v;
    }();
    return all;
}

std::string backend_choices() {
    std::string text;
    for (std::size_t k = 0; k < detail::table_size; ++k) {
        text += k == 0 ? "" : k + 1 == detail::table_size ? " or " : ", ";
        text += detail::table[k].name;
    }
    return text;
}

const char* backend_name(SearchBackend backend) {
    const detail::BackendEntry* e = detail::find_backend(backend);
    return e != nullptr ? e->name : "unknown";
}

SearchBackend parse_backend(const std::string& name) {
    for (const detail::BackendEntry& e : detail::table) {
        if (name == e.name) {
            return e.backend;
        }
    }
    detail::fail<InvalidArgument>("unknown search backend '", name, "' (expected ",
                                  backend_choices(), ")");
}

} // namespace tricell
