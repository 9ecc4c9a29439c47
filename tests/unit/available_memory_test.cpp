// detail::cgroup_memory_limit on control-group trees written into a temporary directory:
// version 2 and version 1 layouts, limits on the group or on a parent, the container layout
// (the group at the mount's root), and trees that set no limit or hold unreadable text.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include <unistd.h>

#include "policy/available_memory.hpp"
#include "tricell/neighbor_list.hpp"

using tricell::detail::cgroup_memory_limit;

namespace {

namespace fs = std::filesystem;

// A fresh directory standing for /sys/fs/cgroup, removed at the end of the test.
class CgroupTree : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
        root_ = fs::temp_directory_path() /
                ("tricell-cgroup-" + std::to_string(getpid()) + "-" + test->name());
        fs::remove_all(root_);
        fs::create_directories(root_);
    }
    void TearDown() override { fs::remove_all(root_); }

    // Writes `text` into root/relative, creating its directories.
    void write(const std::string& relative, const std::string& text) {
        const fs::path path = root_ / relative;
        fs::create_directories(path.parent_path());
        std::ofstream(path) << text << "\n";
    }
    std::optional<std::uint64_t> limit(const std::string& self) const {
        return cgroup_memory_limit(root_.string(), self);
    }

    fs::path root_;
};

} // namespace

TEST_F(CgroupTree, Version2TakesTheGroupsLimit) {
    write("memory.max", "max");
    write("user.slice/memory.max", "max");
    write("user.slice/job/memory.max", "4294967296");
    EXPECT_EQ(limit("0::/user.slice/job\n"), std::uint64_t(4294967296));
}

TEST_F(CgroupTree, Version2TakesTheSmallestLimitOfTheGroupAndItsParents) {
    write("slurm/memory.max", "8000000000");
    write("slurm/job_7/memory.max", "max");
    write("slurm/job_7/step_0/memory.max", "9000000000");
    EXPECT_EQ(limit("0::/slurm/job_7/step_0\n"), std::uint64_t(8000000000));
}

TEST_F(CgroupTree, Version2InAContainerReadsTheMountsRoot) {
    // The container sees its own group as "/" and its limit at the root of the mount.
    write("memory.max", "1073741824");
    EXPECT_EQ(limit("0::/\n"), std::uint64_t(1073741824));
    // A group path from outside the container's namespace that is not mounted here: the root
    // still holds the limit.
    EXPECT_EQ(limit("0::/../../system.slice/docker-1.scope\n"), std::uint64_t(1073741824));
}

TEST_F(CgroupTree, Version1ReadsTheMemoryControllersHierarchyOnly) {
    write("memory/memory.limit_in_bytes", "9223372036854771712"); // version 1's "no limit"
    write("memory/docker/abc/memory.limit_in_bytes", "2147483648");
    write("cpu/docker/abc/memory.limit_in_bytes", "1000"); // not the memory controller
    EXPECT_EQ(limit("5:cpu,cpuacct:/docker/abc\n4:memory:/docker/abc\n1:name=systemd:/\n"),
              std::uint64_t(2147483648));
    // The memory controller named among others on one line.
    EXPECT_EQ(limit("3:cpuset,memory:/docker/abc\n"), std::uint64_t(2147483648));
    // Only the cpu controller's line: its group is not read for a memory limit.
    EXPECT_EQ(limit("5:cpu:/docker/abc\n"), std::nullopt);
}

TEST_F(CgroupTree, NoLimitWhenNothingSetsOneOrTheTextIsNotANumber) {
    EXPECT_EQ(limit(""), std::nullopt);
    EXPECT_EQ(limit("garbage without colons\n"), std::nullopt);
    EXPECT_EQ(limit("0::/missing/group\n"), std::nullopt);
    write("a/memory.max", "max");
    write("memory.max", "-5");
    EXPECT_EQ(limit("0::/a\n"), std::nullopt);
    write("a/memory.max", "12abc");
    write("memory.max", "0");
    EXPECT_EQ(limit("0::/a\n"), std::nullopt);
    write("a/memory.max", "99999999999999999999999");
    EXPECT_EQ(limit("0::/a\n"), std::nullopt);
}

TEST(MaxBytes, DefaultIsThreeQuartersOfTheMemoryThisProcessMayUse) {
    const double physical = double(tricell::detail::physical_memory());
    ASSERT_NEAR(physical, double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE)), 1.0);
    std::ifstream file("/proc/self/cgroup");
    const std::string self((std::istreambuf_iterator<char>(file)),
                           std::istreambuf_iterator<char>());
    const auto cgroup = cgroup_memory_limit("/sys/fs/cgroup", self);
    const double available = cgroup ? std::min(physical, double(*cgroup)) : physical;
    EXPECT_EQ(tricell::NeighborOptions().max_bytes, tricell::default_max_bytes());
    EXPECT_NEAR(double(tricell::default_max_bytes()), 0.75 * available, 1.0);
}
