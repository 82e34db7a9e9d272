/* What a global synchronisation costs beyond its latency on this machine, on 2 ranks: each rank
   repeats a fixed piece of arithmetic (a dependent chain of multiply-adds in registers, so the
   memory plays no part) of about `interval_us` microseconds (argument 1), first `intervals` times
   back to back with no communication, then as many times with an MPI_Allreduce of one double after
   each, as the fix's solve does between its global sums and ghost exchanges.  With the ranks
   running undisturbed the second costs the first plus the latency; whenever one rank is slowed
   (the host takes its core, an interrupt) the other waits at the next synchronisation, so the
   difference measures that jitter at this grain.  Rank 0 prints: the calibrated work per
   interval (us), the slower rank's mean interval without synchronisation (us), the mean interval
   with it (us). */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>

static double chain(long steps, double seed)
{
  double a = seed;
  for (long i = 0; i < steps; i++) a = a * 0.9999999 + 1.0e-9;
  return a;
}

int main(int argc, char **argv)
{
  MPI_Init(&argc, &argv);
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  const double interval_us = argc > 1 ? atof(argv[1]) : 300.0;
  const int intervals = argc > 2 ? atoi(argv[2]) : 3000;

  // steps of the chain per microsecond, measured on rank 0 and shared
  long calibration = 20000000;
  double start = MPI_Wtime();
  double sink = chain(calibration, 1.0);
  double steps_per_us = calibration / ((MPI_Wtime() - start) * 1e6);
  MPI_Bcast(&steps_per_us, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  const long steps = (long) (steps_per_us * interval_us);

  double local = 1.0, total = 0.0;
  MPI_Barrier(MPI_COMM_WORLD);
  start = MPI_Wtime();
  for (int i = 0; i < intervals; i++) sink = chain(steps, sink);
  double alone = (MPI_Wtime() - start) / intervals, slowest = 0.0;
  MPI_Allreduce(&alone, &slowest, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);

  MPI_Barrier(MPI_COMM_WORLD);
  start = MPI_Wtime();
  for (int i = 0; i < intervals; i++) {
    sink = chain(steps, sink);
    local = sink;
    MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  }
  const double synchronised = (MPI_Wtime() - start) / intervals;
  if (me == 0) printf("%.2f %.2f %.2f\n", steps / steps_per_us, slowest * 1e6, synchronised * 1e6);
  if (total == 12345.678) printf("%g\n", sink);    // keeps the chain from being optimised away
  MPI_Finalize();
  return 0;
}
