#pragma once
// The fluid particles near one marker as the markers' kernels take them: n points padded to whole
// pairs (2 * pairs entries; a padding point lies at twice the support, where W = 0): indices j,
// offsets dx = X - x_j, dy and squared distances r2.
namespace sphib {

struct MarkerPoints {
  int pairs = 0;
  const int* j;
  const double *dx, *dy, *r2;
};

}  // namespace sphib
