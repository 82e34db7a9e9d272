/* The two prices of benchmarks/mpi_scaling.py's model, on 2 ranks: the latency of MPI_Allreduce
   of one double (the fix's global sums) and the one-way time per double of a message of
   `doubles` doubles between the ranks (a ghost exchange: argument 1, default 20000), each the
   mean over many calls after a warm-up, printed by rank 0 in microseconds and nanoseconds. */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
  MPI_Init(&argc, &argv);
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  const int doubles = argc > 1 ? atoi(argv[1]) : 20000;

  double local = 1.0, total = 0.0;
  for (int i = 0; i < 1000; i++) MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  const int calls = 100000;
  double start = MPI_Wtime();
  for (int i = 0; i < calls; i++) MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  const double allreduce = (MPI_Wtime() - start) / calls;

  double *buffer = calloc((size_t) doubles, sizeof(double));
  const int other = 1 - me, trips = 2000;
  for (int i = 0; i < trips + 100; i++) {
    if (i == 100) start = MPI_Wtime();
    if (me == 0) {
      MPI_Send(buffer, doubles, MPI_DOUBLE, other, 0, MPI_COMM_WORLD);
      MPI_Recv(buffer, doubles, MPI_DOUBLE, other, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    } else {
      MPI_Recv(buffer, doubles, MPI_DOUBLE, other, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      MPI_Send(buffer, doubles, MPI_DOUBLE, other, 0, MPI_COMM_WORLD);
    }
  }
  const double one_way = (MPI_Wtime() - start) / (2.0 * trips);
  if (me == 0) printf("%.4f %.4f\n", allreduce * 1e6, one_way / doubles * 1e9);
  free(buffer);
  MPI_Finalize();
  return 0;
}
