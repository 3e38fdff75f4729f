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
    case SideKind::Periodic:
    case SideKind::Open: return 0;
  }
  return 0;
}

const char* side_kind_name(SideKind k) {
  switch (k) {
    case SideKind::Periodic: return "periodic";
    case SideKind::NoSlip: return "no_slip";
    case SideKind::Open: return "open";
  }
  return "?";
}

}  // namespace sphib
