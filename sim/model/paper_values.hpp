#pragma once
// The published results of Peshkov & Teitel (constant-phi averaging, narrowest window,
// rate_max = 10^-6.5), in one place: starting values and window centres of the scaling fit,
// the packing from which jamming points are searched, the phi_init check's range, and the
// exponents `jam stats --fix-paper-exponents` holds.
//   2D: phi_J = 0.8415(3), beta = 2.63(9), y = 1.12(4)
//   3D: phi_J = 0.6464(5), beta = 3.07(15), y = 1.22(3)
// With beta = (1 - q) z nu and y = q z nu: z nu = beta + y and q = y / (beta + y).

namespace jam {

struct PaperValues {
  double phi_j, beta, y;
  double phi_j_error, beta_error, y_error;  // the paper's quoted errors (last digits)
  double znu() const { return beta + y; }
  double rate_exponent() const { return y / znu(); }  // q of p ~ rate^q f(x)
  double inv_znu() const { return 1.0 / znu(); }
};

inline constexpr PaperValues paper_values(int dim) {
  return dim == 2 ? PaperValues{0.8415, 2.63, 1.12, 0.0003, 0.09, 0.04}
                  : PaperValues{0.6464, 3.07, 1.22, 0.0005, 0.15, 0.03};
}

}  // namespace jam
