#pragma once
// Independent closed forms for beam-columns (issue 15): nothing here includes liftoff's code.
//
// Hobbs' vertical (upheaval) mode of a heavy member on a RIGID foundation under a compressive
// axial force P (Hobbs 1984, "In-service buckling of heated pipelines", J. Transp. Eng. 110):
// weight q per length toward the foundation (+w), a lifted zone of length L centred at x = 0,
// straight and in contact outside it. In the zone EI w'''' + P w'' = q, n^2 = P / EI:
//   w = A + B cos(n x) + q x^2 / (2 P).
// At the touch-down points x = +-L/2 the member meets the straight part smoothly and with no
// moment (the rigid foundation carries no curvature): w = w' = w'' = 0. Then
//   w'' = 0  ->  B = q / (P n^2 cos(n L/2)),
//   w' = 0   ->  tan(z) = z with z = n L / 2 (the first root above pi: z = 4.4934),
//   w = 0    ->  A = -B cos z - q L^2 / (8 P),
// so P L^2 / EI = 4 z^2 = 80.763, the crown's uplift -w(0) = 2.407e-3 q L^4 / EI and the crown
// moment M(0) = -EI w''(0) = (q L^2 / (4 z^2)) (1/cos z - 1) = -0.06938 q L^2 (hogging), the
// constants the literature quotes (Hobbs 1984, table 1, mode "vertical"). A tensionless
// foundation of modulus K approaches this as K grows (issue 15's verification).

namespace liftoff::closed_form {

struct UpheavalMode {
  double z = 0;               // n L / 2, the first root of tan z = z above pi
  double load_parameter = 0;  // P L^2 / EI = 4 z^2
  double uplift = 0;          // -w(0) EI / (q L^4) > 0: the crown rises
  double crown_moment = 0;    // M(0) / (q L^2), sagging positive (< 0: hogging)
};
UpheavalMode hobbs_vertical_mode();

// The same mode's deflection w(x) EI / (q L^4) at x / L in [-1/2, 1/2] (0 outside: in contact).
double hobbs_vertical_deflection(double x_over_length);

}  // namespace liftoff::closed_form
