#pragma once
/// Reading a whole file: the one reader behind the scene loaders and the image reader, so that every input file is
/// refused for the same reasons in the same words.
#include <cstdint>
#include <string>

#include "core/result.h"

namespace pt {

/// The whole content of the regular file at `path`, or one error "PATH: reason". Anything else (a directory, a FIFO,
/// a device such as /dev/null) is refused unread, and so is a file of more than `max_bytes`. The file is opened
/// without blocking and its type checked on the open descriptor: opening a FIFO for reading would otherwise wait for
/// a writer, and checking the path before opening it could look at another file than the one read.
Result<std::string> read_whole_file(const std::string& path, uint64_t max_bytes);

}  // namespace pt
