// SPDX-License-Identifier: MIT
// The reader's bond list check (store::detail::check_bond_pairs, issue 29 item 3): each bond once
// in each direction. Rows in increasing order (pd-pack's) take the one-pass cursor check, other
// rows a sorted copy; both accept a symmetric list and name the first duplicated, self or
// asymmetric bond.
#include "core/errors.hpp"
#include "h5/file.hpp"
#include "model/model.hpp"
#include "store/model_io_detail.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using namespace pd;

struct Rows {
    std::vector<std::int64_t> offsets{0};
    std::vector<std::int32_t> neighbor;
    void add(std::vector<std::int32_t> row) {
        neighbor.insert(neighbor.end(), row.begin(), row.end());
        offsets.push_back(static_cast<std::int64_t>(neighbor.size()));
    }
};

/// "" when the list passes, else the error's text.
std::string check(const Rows& r) {
    // One file per test: ctest runs this binary's tests as parallel processes, and a shared
    // name made one of them find the other's file locked (a clean-clone CI run failed so).
    const auto path = std::filesystem::temp_directory_path() /
                      (std::string("pd_test_bond_pairs_") +
                       ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".h5");
    std::string what;
    {
        h5::File f(path.string(), h5::Mode::create_truncate);
        try {
            store::detail::check_bond_pairs(f, r.offsets, r.neighbor);
        } catch (const SchemaError& e) {
            what = e.what();
        }
    }
    std::filesystem::remove(path);
    return what;
}

/// Four nodes, bonds 0-1, 0-2, 1-2, 2-3, 1-3; rows in increasing order or turned around.
Rows square(bool increasing) {
    Rows r;
    const std::vector<std::vector<std::int32_t>> rows{{1, 2}, {0, 2, 3}, {0, 1, 3}, {1, 2}};
    for (auto row : rows) {
        if (!increasing)
            std::reverse(row.begin(), row.end());
        r.add(row);
    }
    return r;
}

TEST(BondPairs, SymmetricListsPassInAnyRowOrder) {
    EXPECT_EQ(check(square(true)), "");
    EXPECT_EQ(check(square(false)), "");
    EXPECT_EQ(check(Rows{{0, 0, 0}, {}}), ""); // nodes without bonds
}

TEST(BondPairs, AsymmetricDuplicatedAndSelfBondsAreNamed) {
    for (bool increasing : {true, false}) {
        auto r = square(increasing);
        r.neighbor.pop_back(); // node 3 loses one of its bonds: 1-3 or 2-3 is one-way
        r.offsets.back() -= 1;
        EXPECT_NE(check(r).find("asymmetric bond"), std::string::npos) << increasing;
        Rows one_way; // 0 -> 1 only
        one_way.add({1});
        one_way.add({});
        EXPECT_NE(check(one_way).find("node 0 is bonded to node 1, but node 1 not to node 0"),
                  std::string::npos);
        Rows twice;
        twice.add({1, 1});
        twice.add({0, 0});
        EXPECT_NE(check(twice).find("twice"), std::string::npos);
        Rows self;
        self.add({0, 1});
        self.add({0});
        EXPECT_NE(check(self).find("bonded to itself"), std::string::npos);
    }
    // Each node's count matches but the pairs do not: 0-1, 1-2, 2-0 listed one way round.
    Rows cycle;
    cycle.add({1});
    cycle.add({2});
    cycle.add({0});
    EXPECT_NE(check(cycle).find("asymmetric bond"), std::string::npos);
}

} // namespace
