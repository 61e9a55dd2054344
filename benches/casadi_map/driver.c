/* Times CasADi's generated (+) residual + sparse Jacobian of the periodic Toda lattice built with `map`
   (gen.py): one call of rj(z, q0, p0, h) -> (R, J). Adapted from benches/casadi_scaling/driver.c. The sizes come
   from the generated sparsity patterns, the work-array sizes from rj_work, and the evaluation point (h, z, q0, p0)
   from point.txt written by gen.py.

   usage: map_bench POINT_FILE [batches]
   Each batch times enough evaluations to last about 0.2 s (calibrated once); prints the median over batches:
     ns=<median ns per residual+Jacobian evaluation> evals=<per batch> batches=<count> spread=<max/min - 1> ...  */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "map_gen.h"

static double now(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
static int cmp(const void *a, const void *b) { double x = *(const double *)a, y = *(const double *)b; return (x > y) - (x < y); }
/* number of entries of a CasADi sparsity pattern in its generated compact form: {nrow, ncol, 1} when dense,
   else {nrow, ncol, colind[0] = 0, ..., colind[ncol], row...} */
static casadi_int nnz_of(const casadi_int *sp) { return sp[2] == 1 ? sp[0] * sp[1] : sp[2 + sp[1]]; }

int main(int argc, char **argv) {
  if (argc < 2) { fprintf(stderr, "usage: %s POINT_FILE [batches]\n", argv[0]); return 1; }
  int batches = argc > 2 ? atoi(argv[2]) : 11;
  if (batches < 1) batches = 1;
  casadi_int n = nnz_of(rj_sparsity_in(0));
  casadi_int nres = nnz_of(rj_sparsity_out(0)), njac = nnz_of(rj_sparsity_out(1));
  casadi_int sz_arg, sz_res, sz_iw, sz_w;
  rj_work(&sz_arg, &sz_res, &sz_iw, &sz_w);
  casadi_int *iw = malloc(sizeof(casadi_int) * (sz_iw + 1));
  double *wk = malloc(sizeof(double) * (sz_w + 1));
  const double **arg = malloc(sizeof(double *) * (sz_arg > 4 ? sz_arg : 4));
  double **res = malloc(sizeof(double *) * (sz_res > 2 ? sz_res : 2));
  double *z = malloc(sizeof(double) * n), *q0 = malloc(sizeof(double) * n), *p0 = malloc(sizeof(double) * n);
  double *r = malloc(sizeof(double) * nres), *J = malloc(sizeof(double) * njac), h;
  FILE *f = fopen(argv[1], "r");
  if (!f) { perror(argv[1]); return 1; }
  int ok = fscanf(f, "%lf", &h) == 1;
  for (casadi_int i = 0; i < n; i++) ok &= fscanf(f, "%lf", &z[i]) == 1;
  for (casadi_int i = 0; i < n; i++) ok &= fscanf(f, "%lf", &q0[i]) == 1;
  for (casadi_int i = 0; i < n; i++) ok &= fscanf(f, "%lf", &p0[i]) == 1;
  fclose(f);
  if (!ok) { fprintf(stderr, "%s: expected 1 + 3*%ld numbers\n", argv[1], (long)n); return 1; }
  /* z[0] is small (|z[0]| < 1: particle 0 sits at the origin), so a 1e-15 change is representable; z[n-1] ~ n is not */
  double z0 = z[0], sink = 0;
  /* one evaluation: the unknown varies in its last bits so nothing is hoisted out of the timing loop */
#define EVAL(i)                                                         \
  do {                                                                  \
    z[0] = z0 + 1e-15 * (double)((i) & 7);                              \
    arg[0] = z; arg[1] = q0; arg[2] = p0; arg[3] = &h;                  \
    res[0] = r; res[1] = J;                                             \
    rj(arg, res, iw, wk, 0);                                            \
    sink += r[0] + J[njac - 1];                                         \
  } while (0)
  EVAL(0); /* warm-up: first touch of the work arrays */
  /* calibrate: evaluations lasting about 0.2 s */
  long evals = 1; double t;
  for (;;) { double t0 = now(); for (long i = 0; i < evals; i++) EVAL(i); t = now() - t0; if (t > 0.05 || evals > (1L << 40)) break; evals *= 2; }
  evals = (long)(evals * 0.2 / t) + 1;
  double *per = malloc(sizeof(double) * batches);
  for (int b = 0; b < batches; b++) {
    double t0 = now();
    for (long i = 0; i < evals; i++) EVAL(i);
    per[b] = (now() - t0) / evals * 1e9;
  }
  qsort(per, batches, sizeof(double), cmp);
  printf("ns=%.1f evals=%ld batches=%d spread=%.3f n=%ld nnz=%ld sink=%g\n", per[batches / 2], evals, batches,
         per[batches - 1] / per[0] - 1, (long)n, (long)njac, sink);
  return 0;
}
