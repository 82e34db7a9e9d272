/* Imposed linear flow of a deforming LAMMPS box (shared by lubricate/sf and stokes/sf).

   `fix deform ... remap v` moves the box with shape matrix
       H = [[xprd, xy, xz], [0, yprd, yz], [0, 0, zprd]]
   at rate Hdot = domain->h_rate (Voigt order xx yy zz yz xz xy) and the lower
   corner at domain->h_ratelo.  The streaming velocity that `remap v` and
   `compute temp/deform` assume is u(x) = Hdot H^-1 (x - boxlo) + h_ratelo, i.e.
   the velocity gradient is L = Hdot H^-1 (L_ij = du_i/dx_j) and the imposed
   angular velocity is Omega = curl(u)/2.  For `xz erate cos(t) yz erate sin(t)`
   this gives L_xz = gammadot cos t, L_yz = gammadot sin t (the tilt RATE divided
   by zprd) and Omega = gammadot/2 (-sin t, cos t, 0). */

#ifndef SUSPENSION_FABRIC_IMPOSED_FLOW_H
#define SUSPENSION_FABRIC_IMPOSED_FLOW_H

#include "domain.h"

namespace SuspensionFabric {

struct ImposedFlow {
  double grad[3][3];    // L_ij = du_i/dx_j
  double strain[3][3];  // E = (L + L^T)/2
  double omega[3];      // (1/2) curl u
  double origin[3];     // box lower corner
  double offset[3];     // velocity of the lower corner (h_ratelo)

  explicit ImposedFlow(const LAMMPS_NS::Domain *domain)
  {
    const double *h = domain->h;
    const double *hr = domain->h_rate;
    // H^-1 of the upper-triangular shape matrix, written out
    const double hinv[3][3] = {
        {1.0 / h[0], -h[5] / (h[0] * h[1]), (h[5] * h[3] - h[4] * h[1]) / (h[0] * h[1] * h[2])},
        {0.0, 1.0 / h[1], -h[3] / (h[1] * h[2])},
        {0.0, 0.0, 1.0 / h[2]}};
    const double hdot[3][3] = {{hr[0], hr[5], hr[4]}, {0.0, hr[1], hr[3]}, {0.0, 0.0, hr[2]}};
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        grad[i][j] = 0.0;
        for (int k = 0; k < 3; k++) grad[i][j] += hdot[i][k] * hinv[k][j];
      }
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) strain[i][j] = 0.5 * (grad[i][j] + grad[j][i]);
    omega[0] = 0.5 * (grad[2][1] - grad[1][2]);
    omega[1] = 0.5 * (grad[0][2] - grad[2][0]);
    omega[2] = 0.5 * (grad[1][0] - grad[0][1]);
    for (int k = 0; k < 3; k++) {
      origin[k] = domain->boxlo[k];
      offset[k] = domain->h_ratelo[k];
    }
  }

  void velocity(const double *x, double *u) const
  {
    const double d[3] = {x[0] - origin[0], x[1] - origin[1], x[2] - origin[2]};
    for (int i = 0; i < 3; i++)
      u[i] = grad[i][0] * d[0] + grad[i][1] * d[1] + grad[i][2] * d[2] + offset[i];
  }
};

}    // namespace SuspensionFabric

#endif
