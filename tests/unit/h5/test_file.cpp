// SPDX-License-Identifier: MIT
// The HDF5 layer: round trips of every element type, extendible appends, attributes, and errors
// that name the file and the dataset path.
#include "h5/file.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace {

using namespace pd;

std::string tmp(const char* name) {
    return (std::filesystem::temp_directory_path() / name).string();
}

TEST(H5, RoundTrip) {
    const auto p = tmp("pd_h5_roundtrip.h5");
    {
        h5::File f(p, h5::Mode::create_truncate);
        f.write("/a/b/x", std::vector<double>{1, 2, 3, 4, 5, 6}, {2, 3});
        f.write("/a/i", std::vector<std::int32_t>{-1, 7});
        f.write("/a/u8", std::vector<std::uint8_t>{0, 255});
        f.write_scalar("/a/s", std::int64_t{42});
        f.write_string("/p/text", "héllo {json}");
        f.set_attr("/a/b/x", "unit", "m");
        f.set_attr("/", "version", std::vector<std::int32_t>{1, 1});
        f.set_attr("/a", "names", std::vector<std::string>{"none", "none"});
        f.create_extendible<double>("/e/value", {2}, 4);
        f.append<double>("/e/value", std::vector<double>{1, 2}, 1);
        f.append<double>("/e/value", std::vector<double>{3, 4, 5, 6}, 2);
    }
    h5::File f(p, h5::Mode::read);
    h5::dims_t d;
    auto x = f.read<double>("/a/b/x", &d);
    EXPECT_EQ(d, (h5::dims_t{2, 3}));
    EXPECT_EQ(x[5], 6.0);
    EXPECT_EQ(f.read<std::int32_t>("/a/i")[0], -1);
    EXPECT_EQ(f.read<std::uint8_t>("/a/u8")[1], 255);
    EXPECT_EQ(f.read_scalar<std::int64_t>("/a/s"), 42);
    EXPECT_EQ(f.read_string("/p/text"), "héllo {json}");
    EXPECT_EQ(f.attr_string("/a/b/x", "unit"), "m");
    EXPECT_EQ(f.attr_vector<std::int32_t>("/", "version"), (std::vector<std::int32_t>{1, 1}));
    EXPECT_EQ(f.shape("/e/value"), (h5::dims_t{3, 2}));
    EXPECT_EQ(f.read_rows<double>("/e/value", 1, 2), (std::vector<double>{3, 4, 5, 6}));
    EXPECT_TRUE(f.exists("/a/b"));
    EXPECT_FALSE(f.exists("/a/zz/q"));
    EXPECT_EQ(f.list("/a"), (std::vector<std::string>{"b", "i", "s", "u8"}));
}

TEST(H5, MissingDatasetNamesFileAndPath) {
    const auto p = tmp("pd_h5_missing.h5");
    { h5::File f(p, h5::Mode::create_truncate); }
    h5::File f(p, h5::Mode::read);
    try {
        f.read<double>("/nodes/volume");
        FAIL() << "no throw";
    } catch (const InputError& e) {
        const std::string w = e.what();
        EXPECT_NE(w.find(p), std::string::npos) << w;
        EXPECT_NE(w.find("/nodes/volume"), std::string::npos) << w;
    }
}

TEST(H5, TruncatedFileIsAnInputError) {
    const auto p = tmp("pd_h5_trunc.h5");
    {
        h5::File f(p, h5::Mode::create_truncate);
        f.write("/x", std::vector<double>(10000, 1.0));
    }
    std::filesystem::resize_file(p, 1000);
    EXPECT_THROW(h5::File(p, h5::Mode::read).read<double>("/x"), InputError);
    EXPECT_THROW(h5::File(tmp("pd_h5_does_not_exist.h5"), h5::Mode::read), InputError);
}

} // namespace
