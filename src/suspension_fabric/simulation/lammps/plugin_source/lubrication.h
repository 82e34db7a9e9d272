/* Leading-order pairwise lubrication resistance (Jeffrey & Onishi 1984; Mari et al. 2014),
   shared by pair_style lubricate/sf (explicit forces) and fix hydro/implicit/sf (implicit
   solve), so both use one set of formulas, and the pair's stresslet (Jeffrey 1992).
   Conventions and prefactors: see the header comment of pair_lubricate_sf.cpp. */

#ifndef SUSPENSION_FABRIC_LUBRICATION_H
#define SUSPENSION_FABRIC_LUBRICATION_H

#include <cmath>

namespace SuspensionFabric {

// Resistance scalars of one pair and its unit vector n from i to j.
struct PairResistance {
  double n[3];
  double X, YA, YBi, YBj, YCi, YCj, YCx;
  double ai, aj, invxi, logxi;    // radii, 1/xi_r and log(1/xi_r), for the stresslet
};

/* Resistances of the pair (i, j) with separation del = x_i - x_j and radii ai, aj.
   Returns false if the reduced gap xi = 2h/(ai + aj) is at or beyond gap_out. */
inline bool lubrication_resistance(const double del[3], double ai, double aj, double eta_f,
                                   double delta, double gap_out, PairResistance &out)
{
  const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
  const double radsum = ai + aj;
  const double rcut = radsum * (1.0 + 0.5 * gap_out);
  if (rsq >= rcut * rcut) return false;

  const double r = std::sqrt(rsq);
  const double rinv = 1.0 / r;
  for (int k = 0; k < 3; k++) out.n[k] = -del[k] * rinv;    // from i to j

  const double gap = 2.0 * (r - radsum) / radsum;
  const double xi = (gap > 0.0 ? gap : 0.0) + delta;
  const double invxi = 1.0 / xi;
  const double logxi = std::log(invxi);

  const double pi_eta = M_PI * eta_f;
  const double l = aj / ai;
  const double ilp1 = 1.0 / (1.0 + l);
  const double ilp1_2 = ilp1 * ilp1;
  const double ilp1_3 = ilp1_2 * ilp1;
  out.ai = ai;
  out.aj = aj;
  out.invxi = invxi;
  out.logxi = logxi;

  out.X = 6.0 * pi_eta * ai * (2.0 * l * l * ilp1_3) * invxi;
  out.YA = 6.0 * pi_eta * ai * ((4.0 / 15.0) * l * (2.0 + l + 2.0 * l * l) * ilp1_3) * logxi;
  out.YBi = 4.0 * pi_eta * ai * ai * (-0.2 * l * (4.0 + l) * ilp1_2) * logxi;
  out.YBj = 4.0 * pi_eta * aj * aj * (-0.2 * (4.0 * l + 1.0) * ilp1_2) * logxi;
  out.YCi = 8.0 * pi_eta * ai * ai * ai * (0.4 * l * ilp1) * logxi;
  out.YCj = 8.0 * pi_eta * aj * aj * aj * (0.4 * ilp1) * logxi;
  out.YCx = pi_eta * radsum * radsum * radsum * (0.8 * l * l * ilp1_2 * ilp1_2) * logxi;
  return true;
}

/* Force on i (fi; j gets -fi) and torques on i and j for the relative velocity du and the
   angular velocities wi, wj (all relative to the imposed flow, see pair_lubricate_sf.cpp):
     F_i = -X (n.du) n - YA P du - YBi n x w_i - YBj n x w_j
     T_i = -YBi du x n - P (YCi w_i + YCx w_j),   T_j = -YBj du x n - P (YCx w_i + YCj w_j)
   (R: a PairResistance, or any struct with n and these seven coefficients) */
template <class Resistance>
inline void lubrication_forces(const Resistance &R, const double du[3], const double wi[3],
                               const double wj[3], double fi[3], double ti[3], double tj[3])
{
  const double *n = R.n;
  const double un = du[0] * n[0] + du[1] * n[1] + du[2] * n[2];
  const double win = wi[0] * n[0] + wi[1] * n[1] + wi[2] * n[2];
  const double wjn = wj[0] * n[0] + wj[1] * n[1] + wj[2] * n[2];
  const double nxwi[3] = {n[1] * wi[2] - n[2] * wi[1], n[2] * wi[0] - n[0] * wi[2],
                          n[0] * wi[1] - n[1] * wi[0]};
  const double nxwj[3] = {n[1] * wj[2] - n[2] * wj[1], n[2] * wj[0] - n[0] * wj[2],
                          n[0] * wj[1] - n[1] * wj[0]};
  const double duxn[3] = {du[1] * n[2] - du[2] * n[1], du[2] * n[0] - du[0] * n[2],
                          du[0] * n[1] - du[1] * n[0]};
  for (int k = 0; k < 3; k++) {
    const double dut = du[k] - un * n[k];
    const double wit = wi[k] - win * n[k];
    const double wjt = wj[k] - wjn * n[k];
    fi[k] = -R.X * un * n[k] - R.YA * dut - R.YBi * nxwi[k] - R.YBj * nxwj[k];
    ti[k] = -R.YBi * duxn[k] - R.YCi * wit - R.YCx * wjt;
    tj[k] = -R.YBj * duxn[k] - R.YCx * wit - R.YCj * wjt;
  }
}

/* Stresslet of the pair, S_i + S_j, at leading order (Jeffrey 1992, Phys. Fluids A 4, 16;
   the singular parts of X^G, Y^G, Y^H, X^M, Y^M):
     S_a = -sum_b [G_ab.(U_b - U_inf(x_b)) + H_ab.(w_b)] + sum_b M_ab : E_inf.
   At leading order G_ij = -G_ii, and sum_b M_ab : E_inf = -G_ii.(E_inf.(x_i - x_j)) with the
   pair at contact distance, x_i - x_j = -(a_i + a_j) n (the M functions are those of G times
   the contact distance).  So S depends on one relative velocity,
     du_S = (U_i - U_inf(x_i)) - (U_j - U_inf(x_j)) - (a_i + a_j) E_inf.n,
   the velocity relative to the imposed flow plus the imposed strain velocity at contact
   (the forces use the strain velocity at the actual distance, E_inf.(x_i - x_j)).  The
   function takes du_na = (U_i - U_inf(x_i)) - (U_j - U_inf(x_j)) and E_inf:
     S = -(XG_i + XG_j) (n.du_S) (nn - I/3) - (YG_i + YG_j) (n du_t + du_t n)
         - [(YH_ii + YH_ji) w_i x n + (YH_ij + YH_jj) w_j x n] n  (symmetrised)
   with, for lambda = a_j/a_i, L = log(1/xi_r):
     XG_i  = 4 pi eta a_i^2 (3 l^2/(1+l)^3) / xi_r
     YG_i  = 4 pi eta a_i^2 (l (4 - l + 7 l^2) / (10 (1+l)^3)) L
     YH_ii = 8 pi eta a_i^3 (l (2 - l) / (10 (1+l)^2)) L
     YH_ij = 8 pi eta a_i^3 (l^2 (1 + 7 l) / (20 (1+l)^2)) L
   and the j functions with i <-> j, l -> 1/l.  At this order S is (a_i + a_j) times the
   traceless symmetric part of n F_i (the force dipole at contact distance; tested).  S is
   traceless (no particle pressure: the force dipole keeps that).  Order xx yy zz xy xz yz;
   S > 0 is tensile. */
inline void lubrication_stresslet(const PairResistance &R, const double eta_f, const double du_na[3],
                                  const double E[3][3], const double wi[3], const double wj[3], double S[6])
{
  const double *n = R.n;
  const double contact = R.ai + R.aj;
  double du[3];    // du_S
  for (int a = 0; a < 3; a++) du[a] = du_na[a] - contact * (E[a][0] * n[0] + E[a][1] * n[1] + E[a][2] * n[2]);
  const double fourpi = 4.0 * M_PI * eta_f;
  const double ai = R.ai, aj = R.aj;
  const double l = aj / ai, m = ai / aj;    // lambda seen from i and from j
  const double lp1 = 1.0 + l, mp1 = 1.0 + m;
  const double XG = fourpi * R.invxi * (ai * ai * 3.0 * l * l / (lp1 * lp1 * lp1) +
                                        aj * aj * 3.0 * m * m / (mp1 * mp1 * mp1));
  const double YG = fourpi * R.logxi * (ai * ai * l * (4.0 - l + 7.0 * l * l) / (10.0 * lp1 * lp1 * lp1) +
                                        aj * aj * m * (4.0 - m + 7.0 * m * m) / (10.0 * mp1 * mp1 * mp1));
  const double eightpiL = 2.0 * fourpi * R.logxi;
  const double ai3 = ai * ai * ai, aj3 = aj * aj * aj;
  const double YHii = eightpiL * ai3 * l * (2.0 - l) / (10.0 * lp1 * lp1);
  const double YHij = eightpiL * ai3 * l * l * (1.0 + 7.0 * l) / (20.0 * lp1 * lp1);
  const double YHjj = eightpiL * aj3 * m * (2.0 - m) / (10.0 * mp1 * mp1);
  const double YHji = eightpiL * aj3 * m * m * (1.0 + 7.0 * m) / (20.0 * mp1 * mp1);
  const double cwi = YHii + YHji, cwj = YHij + YHjj;

  const double un = du[0] * n[0] + du[1] * n[1] + du[2] * n[2];
  double t[3];    // YG du_t + the rotation vector, both symmetrised with n below
  for (int k = 0; k < 3; k++) t[k] = YG * (du[k] - un * n[k]);
  const double wixn[3] = {wi[1] * n[2] - wi[2] * n[1], wi[2] * n[0] - wi[0] * n[2],
                          wi[0] * n[1] - wi[1] * n[0]};
  const double wjxn[3] = {wj[1] * n[2] - wj[2] * n[1], wj[2] * n[0] - wj[0] * n[2],
                          wj[0] * n[1] - wj[1] * n[0]};
  for (int k = 0; k < 3; k++) t[k] += cwi * wixn[k] + cwj * wjxn[k];
  const double sq = -XG * un;
  static const int a[6] = {0, 1, 2, 0, 0, 1}, b[6] = {0, 1, 2, 1, 2, 2};
  for (int c = 0; c < 6; c++) {
    const double iso = (a[c] == b[c]) ? 1.0 / 3.0 : 0.0;
    S[c] = sq * (n[a[c]] * n[b[c]] - iso) - (n[a[c]] * t[b[c]] + t[a[c]] * n[b[c]]);
  }
}

}    // namespace SuspensionFabric

#endif
