/* Frictional Hooke contacts with implicit springs, for fix hydro/implicit/sf (keyword
   `contacts`).  The same contact law as LAMMPS `pair granular hooke <kn> 0 tangential
   linear_history <kt> 0 <mu>` (the explicit path of this project):

     normal      F_n = kn o n,                 o = a_i + a_j - r (overlap), n = (x_i - x_j)/r
     tangential  F_t = -kt xi, |F_t| <= mu F_n  (Coulomb; a capped contact slides and its
                 spring is reset to xi = -F_t/kt, as LAMMPS does)
                 with a critical load F_CL > 0 (keyword critical_load; Mari, Seto, Morris and
                 Denn, J. Rheol. 58, 1693, 2014): |F_t| <= mu (F_n - F_CL) while F_n > F_CL, and
                 F_t = 0 with the spring reset to xi = 0 while F_n <= F_CL, so a contact that
                 turns frictionless forgets its spring (as LF_DEM's critical-load law does)
     torques     T_i = -l_i n x F_t,  T_j = -l_j n x F_t,   l = a - o/2 (lever arm to the contact)

   where xi is the accumulated tangential displacement of i relative to j at the contact,
   projected each step onto the current tangent plane with its length kept (LAMMPS
   linear_history), and the slip velocity that feeds it is
     s = P (v_i - v_j) - (l_i omega_i + l_j omega_j) x n,    P = I - n n.
   (LAMMPS uses a_i, a_j instead of l_i, l_j in s; l makes the spring's operator symmetric,
   and the difference is of order o/a ~ 1e-5.)  The normal spring, taken implicitly, pushes
   with kn (o - dt s_n), the overlap at the end of the step, s_n = (v_i - v_j) . n the rate at
   which the pair separates: it adds kn dt n n to the pair's translational blocks.  Virtual work: the slip is B (v, omega) and
   the tangential force and torques are B^T F_t, so a spring acting on the slip adds the
   symmetric positive semi-definite block kt dt B^T B to the implicit operator. */

#ifndef SUSPENSION_FABRIC_CONTACT_H
#define SUSPENSION_FABRIC_CONTACT_H

#include <cmath>

namespace SuspensionFabric {

struct Contact {
  int i, j;              // local indices; j is the owner of a ghost partner
  int pair;              // index of the lubricated pair (i, j)
  double n[3];           // (x_i - x_j) / r: from j to i
  double del[3];         // x_i - x_j
  double li, lj;         // lever arms a - o/2
  double overlap;        // o at the start of the step (> 0)
  double normal_force;   // kn o
  double friction_bound; // the Coulomb bound mu max(kn o - F_CL, 0); 0: frictionless this step
  double flow_approach;  // n . E (x_i - x_j): separation rate of the imposed flow
  double solved_normal;  // normal force of the solved step
  double spring[3];      // xi of the last step, projected onto the current tangent plane
  double flow_slip[3];   // slip of the imposed flow, P E (x_i - x_j)
  double sliding_force[3];    // tangential force of a sliding contact (explicit)
  double sliding_direction[3];  // unit trial spring of a sliding contact (solve newton)
  double sliding_stiffness;     // bound / |trial spring|: its stiffness across that direction (solve newton)
  int changes;           // changes of sticking or pressed in this step's passes (solve newton)
  double force[3];       // tangential force on i after the step
  double history_sign;   // +1 if the history is stored for (i, j), -1 for (j, i)
  unsigned long long key;
  bool sticking;         // spring implicit (in the operator); else the Coulomb force, explicit
  bool pressed;          // normal spring implicit, kn (o - dt s_n); else kn o, explicit
};

inline double dot3(const double *a, const double *b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

inline void cross3(const double *a, const double *b, double *c)
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

/* Slip velocity s = P du - (l_i w_i + l_j w_j) x n of the contact for the relative
   translational velocity du = u_i - u_j and the angular velocities w_i, w_j. */
inline void contact_slip(const Contact &c, const double *du, const double *wi, const double *wj,
                         double *s)
{
  const double un = dot3(du, c.n);
  const double w[3] = {c.li * wi[0] + c.lj * wj[0], c.li * wi[1] + c.lj * wj[1],
                       c.li * wi[2] + c.lj * wj[2]};
  double wxn[3];
  cross3(w, c.n, wxn);
  for (int k = 0; k < 3; k++) s[k] = du[k] - un * c.n[k] - wxn[k];
}

/* Torques on i and j of a tangential force f on i (and -f on j) acting at the contact. */
inline void contact_torques(const Contact &c, const double *f, double *ti, double *tj)
{
  double nxf[3];
  cross3(c.n, f, nxf);
  for (int k = 0; k < 3; k++) {
    ti[k] = -c.li * nxf[k];
    tj[k] = -c.lj * nxf[k];
  }
}

/* Projects a spring displacement onto the plane normal to n, keeping its length. */
inline void project_spring(const double *n, double *xi)
{
  const double length = std::sqrt(dot3(xi, xi));
  const double along = dot3(xi, n);
  for (int k = 0; k < 3; k++) xi[k] -= along * n[k];
  const double projected = std::sqrt(dot3(xi, xi));
  const double scale = projected > 0.0 ? length / projected : 0.0;
  for (int k = 0; k < 3; k++) xi[k] *= scale;
}

}    // namespace SuspensionFabric

#endif
