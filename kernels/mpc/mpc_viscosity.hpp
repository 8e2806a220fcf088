// mpc_viscosity.hpp — the shear viscosity of the MPC-AT+a fluid, eq. (B.3) of the crystal paper
// (Noguchi & Gompper's result for large n): kinetic plus collisional part,
//   η = n k_BT h/a^d (n/(n − (d + 2)/4) − 1/2) + m (n − 1.4)/(24 a^{d−2} h),
// n particles per cell of size a, particle mass m, time step h, dimension d. Host-callable.
#pragma once

#include <cmath>

namespace mesoflow::mpc {

inline double at_plus_a_viscosity(double n, double kT, double mass, double h, double a, double d = 2) {
  return n * kT * h / std::pow(a, d) * (n / (n - (d + 2) / 4) - 0.5) + mass * (n - 1.4) / (24 * std::pow(a, d - 2) * h);
}

}  // namespace mesoflow::mpc
