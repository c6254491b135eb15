// The communication cost of one reduction of a distributed render (src/dist): the time Cluster::sum_films takes to
// sum every Film buffer of K ranks at rank 0, and the latency of the stop vote (Cluster::any, one MPI_Allreduce).
// Run under mpirun: `mpirun -np 2 build/bench/bench_mpi_reduce [--csv FILE]`. Without mpirun it reports one rank
// (a copy). Table on stdout, CSV rows: ranks,width,height,bytes,ms_per_reduction,gb_per_s,vote_us.
#include <chrono>
#include <cstdio>
#include <string>

#include "bench_cli.h"
#include "dist/cluster.h"

using namespace pt;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
  std::string csv_path;
  int repeats = 5;
  CLI::App app{"The cost of one reduction of a distributed render and of the stop vote; run under mpirun.",
               "bench_mpi_reduce"};
  app.add_option("--csv", csv_path, "CSV output (default: none)");
  app.add_option("--repeats", repeats, "Reductions timed per size (default 5)")->check(CLI::Range(1, 1 << 20));
  if (std::optional<int> exit_code = bench::parse_command_line(app, argc, argv)) return *exit_code;
  std::unique_ptr<Cluster> cluster = join_cluster();
  const int sizes[][2] = {{512, 512}, {1920, 1080}, {3840, 2160}};
  std::string csv = "ranks,width,height,bytes,ms_per_reduction,gb_per_s,vote_us\n";
  if (cluster->root())
    std::printf("%5s %11s %10s %12s %9s %9s\n", "ranks", "size", "MB", "ms/reduce", "GB/s", "vote us");
  for (const auto& wh : sizes) {
    Film local(wh[0], wh[1]), total;
    for (size_t p = 0; p < local.count.size(); ++p) local.add(p, vec3(float(p % 7), 1.0f, 0.5f));
    size_t bytes = 0;
    local.for_each_buffer([&](auto span) { bytes += span.size_bytes(); });
    double best_ms = 1e30, best_vote_us = 1e30;
    for (int r = 0; r < repeats; ++r) {
      cluster->any(false);  // all ranks start together
      auto t0 = Clock::now();
      cluster->sum_films(local, total);
      cluster->any(false);  // ... and the time is the slowest rank's
      best_ms = std::min(best_ms, std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      auto t1 = Clock::now();
      for (int v = 0; v < 100; ++v) cluster->any(false);
      best_vote_us = std::min(best_vote_us, std::chrono::duration<double, std::micro>(Clock::now() - t1).count() / 100);
    }
    // Bytes that rank 0 receives: one film per tree level (log2 K levels).
    double gbps = best_ms > 0 ? double(bytes) / (best_ms * 1e-3) * 1e-9 : 0.0;
    if (cluster->root()) {
      char size[32], row[160];
      std::snprintf(size, sizeof size, "%dx%d", wh[0], wh[1]);
      std::printf("%5d %11s %10.1f %12.2f %9.2f %9.1f\n", cluster->ranks(), size, bytes / 1e6, best_ms, gbps,
                  best_vote_us);
      std::snprintf(row, sizeof row, "%d,%d,%d,%zu,%.4f,%.3f,%.2f\n", cluster->ranks(), wh[0], wh[1], bytes, best_ms,
                    gbps, best_vote_us);
      csv += row;
    }
  }
  if (cluster->root() && !csv_path.empty()) {
    if (FILE* f = std::fopen(csv_path.c_str(), "w")) {
      std::fputs(csv.c_str(), f);
      std::fclose(f);
    }
  }
  return 0;
}
