#pragma once
// What a path that is not a regular file is, in the words both the reader and the writer use in
// their one-line refusals ("a FIFO, not a regular file").
#include <string>

#include <sys/stat.h>

namespace gt::io {

[[nodiscard]] inline std::string fileKind(mode_t mode) {
    if (S_ISREG(mode)) return "a regular file";
    if (S_ISDIR(mode)) return "a folder";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISSOCK(mode)) return "a socket";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISLNK(mode)) return "a symlink";
    return "not a regular file";
}

} // namespace gt::io
