// SPDX-License-Identifier: MIT
// A pd-file holds its own data (issue 27): an external link, a user-defined link, a virtual
// dataset or a dataset with external raw storage would make a tool read from, or write into,
// another file that no lock protects. Refused at open, naming the object.
#include "h5/detail.hpp"

#include <string>

namespace pd::h5::detail {

namespace {

struct Scan {
    std::string path; ///< first object that points outside the file
    std::string why;
};

std::string dataset_elsewhere(hid_t file, const std::string& path) {
    H5O_info_t info;
    if (H5Oget_info_by_name(file, path.c_str(), &info, H5P_DEFAULT) < 0) {
        H5Eclear2(H5E_DEFAULT);
        return "";
    }
    if (info.type != H5O_TYPE_DATASET)
        return "";
    const Handle d(H5Dopen2(file, path.c_str(), H5P_DEFAULT));
    if (!d.valid()) {
        H5Eclear2(H5E_DEFAULT);
        return "";
    }
    const Handle dcpl(H5Dget_create_plist(d.get()));
    if (!dcpl.valid())
        return "";
    if (H5Pget_layout(dcpl.get()) == H5D_VIRTUAL)
        return "is a virtual dataset (its data live in other files)";
    if (H5Pget_external_count(dcpl.get()) > 0)
        return "stores its data in an external file";
    return "";
}

herr_t visit(hid_t group, const char* name, const H5L_info_t* info, void* data) {
    auto* s = static_cast<Scan*>(data);
    const std::string path = "/" + std::string(name);
    if (info->type == H5L_TYPE_EXTERNAL) {
        s->path = path;
        s->why = "is an external link (to another file)";
        return 1;
    }
    if (info->type != H5L_TYPE_HARD && info->type != H5L_TYPE_SOFT) {
        s->path = path;
        s->why = "is a user-defined link";
        return 1;
    }
    if (info->type == H5L_TYPE_HARD) {
        const std::string why = dataset_elsewhere(group, path);
        if (!why.empty()) {
            s->path = path;
            s->why = why;
            return 1;
        }
    }
    return 0; // a soft link names a path of this file: its target is checked as itself
}

} // namespace

void refuse_links_elsewhere(hid_t file, const std::string& name) {
    Scan s;
    if (H5Lvisit(file, H5_INDEX_NAME, H5_ITER_NATIVE, visit, &s) < 0 && s.path.empty()) {
        H5Eclear2(H5E_DEFAULT);
        throw Error(name, "/", "cannot list the objects of the file (damaged?)");
    }
    if (!s.path.empty())
        throw Error(name, s.path,
                    s.why + "; a pd-file must hold its own data, refused (remove it, or copy "
                            "the data in with h5copy)");
}

} // namespace pd::h5::detail
