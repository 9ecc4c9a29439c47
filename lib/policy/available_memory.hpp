// The memory this process may use, the base of NeighborOptions::max_bytes's default.
//
// It is the smaller of the machine's physical memory (sysconf) and the memory limit of the
// process's control group, the mechanism by which containers, batch schedulers (Slurm's
// cgroup plugin) and systemd services cap a process below the machine. The group is the path
// of /proc/self/cgroup; every group from it up to the root can carry a limit, and the smallest
// one holds. Version 2 writes a limit in memory.max ("max" for none), version 1 in
// memory/memory.limit_in_bytes (a number near 2^63 for none). Inside a container the process's
// own group is usually mounted at the root of /sys/fs/cgroup, so the walk reads the root too.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace tricell::detail {

/// The smallest memory limit in bytes of the control groups of a process whose
/// /proc/self/cgroup reads `self_cgroup`, with the cgroup file systems mounted under `root`
/// ("/sys/fs/cgroup"); nullopt when no group sets one (or none can be read).
std::optional<std::uint64_t> cgroup_memory_limit(const std::string& root,
                                                 const std::string& self_cgroup);

/// The physical memory in bytes (sysconf); 0 where the system does not say.
std::uint64_t physical_memory();

} // namespace tricell::detail
