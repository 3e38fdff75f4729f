#include "fluid/common/boundary_rule.hpp"

namespace sphib {

int image_parity(SideKind k, Field f) {
  switch (k) {
    case SideKind::NoSlip:
      switch (f) {
        case Field::VelocityNormal:
        case Field::VelocityTangential: return -1;  // u_img = 2 U_wall - u (Eq. 42)
        case Field::Scalar: return +1;              // phi_img = phi (Eq. 9)
        case Field::Stream: return -1;              // psi_img = 2 psi_w - psi
      }
      break;
    case SideKind::Inflow:
      switch (f) {
        case Field::VelocityNormal:
        case Field::VelocityTangential: return -1;  // u_img = 2 u_in - u: u = u_in on the side (Eq. 42's form)
        case Field::Scalar: return +1;              // dphi/dn = 0
        case Field::Stream: return -1;              // psi_img = 2 psi_in - psi, psi_in = int u_n along the side
      }
      break;
    case SideKind::Outflow:
      switch (f) {
        case Field::VelocityNormal:
        case Field::VelocityTangential: return +1;  // du/dn = 0 (zero gradient)
        case Field::Scalar: return -1;              // phi = 0 (the pressure's reference)
        case Field::Stream: return +1;              // dpsi/dn = 0: d(u_n)/dn = d^2 psi/dn ds = 0, u_t = 0
      }
      break;
    case SideKind::FreeSlip:
      switch (f) {
        case Field::VelocityNormal: return -1;      // u_n = 0 on the wall (impermeable)
        case Field::VelocityTangential: return +1;  // du_t/dn = 0 (no shear)
        case Field::Scalar: return +1;              // dphi/dn = 0 (Eq. 9)
        case Field::Stream: return -1;              // psi constant along the wall
      }
      break;
    case SideKind::Periodic:
    case SideKind::Open: return 0;
  }
  return 0;
}

double profile_integral(InflowProfile p, double s) {
  if (p == InflowProfile::Parabolic) return s * s * (2.0 - 4.0 * s / 3.0);  // int_0^s 4 t (1 - t) dt
  return s;                                                                // int_0^s 1 dt
}

const char* side_kind_name(SideKind k) {
  switch (k) {
    case SideKind::Periodic: return "periodic";
    case SideKind::NoSlip: return "no_slip";
    case SideKind::Open: return "open";
    case SideKind::Inflow: return "inflow";
    case SideKind::Outflow: return "outflow";
    case SideKind::FreeSlip: return "free_slip";
  }
  return "?";
}

}  // namespace sphib
