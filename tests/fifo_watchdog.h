#pragma once
// Loading from a FIFO without letting a regression hang the test: opening a FIFO for reading waits for a writer, so a
// reader that opens before it checks the file type would block the test forever.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <future>
#include <string>

namespace pt::test {

/// Runs `load()`, which reads the FIFO `fifo`, on another thread and returns its result. If the load is still
/// waiting after 20 s, the test fails and a writer is opened on the FIFO, so the load reads an empty file and returns
/// instead of the test hanging.
template <class Load>
auto load_with_fifo_watchdog(const std::string& fifo, Load load) {
  auto loading = std::async(std::launch::async, load);
  if (loading.wait_for(std::chrono::seconds(20)) != std::future_status::ready) {
    ADD_FAILURE() << "the load is waiting on the FIFO " << fifo;
    const int writer = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
    if (writer >= 0) ::close(writer);
  }
  return loading.get();
}

}  // namespace pt::test
