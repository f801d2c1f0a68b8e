// SPDX-License-Identifier: MIT
// What a run reads and writes on the file system (issue 27): inputs must be regular files (a FIFO
// or /dev/zero as a scene, mesh or pd-file would hang the reader), every input is remembered by
// device + inode so that no output of the run replaces it under any name (symlink, hard link,
// relative path), and side files (`.reserve`, `.tmp.*`) are created exclusively, never through a
// link.
#pragma once

#include <string>
#include <sys/types.h>
#include <utility>

namespace pd {

/// "a directory", "a FIFO", "a socket", "a character device", "a block device", "a symbolic
/// link", "a regular file", "something else", for `st_mode`.
std::string file_kind(mode_t st_mode);

/// Refuses (InputError, exit 2) an input `path` (`what`: "scene", "mesh", ...) that exists and is
/// not a regular file, naming what it is; then records its device + inode as read by this run.
/// A path that does not exist passes (the reader reports it).
void note_input(const std::string& what, const std::string& path);

/// The role and path of a recorded input that is the same file as `path` (device + inode,
/// through links), or {"", ""}.
std::pair<std::string, std::string> read_input_same_as(const std::string& path);

/// Refuses an output `path` (given as `option`) that exists and is not a regular file (a
/// directory, device, FIFO or socket: writing would replace or block on it), or that is an input
/// this run has read (note_input). Called before the output is written.
void check_output_target(const std::string& option, const std::string& path);

/// Creates the side file `path` for writing with O_CREAT | O_EXCL | O_NOFOLLOW: a leftover of a
/// killed run under that name (a regular file, or a link someone planted) is unlinked first, never
/// followed nor truncated. Returns the descriptor, or -1 with errno set. A directory there is
/// left alone (EISDIR).
int create_side_file(const std::string& path);

} // namespace pd
