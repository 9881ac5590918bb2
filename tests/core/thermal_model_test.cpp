#include "core/thermal_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "tests/support/thermal_examples.hpp"

namespace tofcomp::core {
namespace {

// Eq. 3 written out independently of core/: the right-hand side for state x and inputs u, t^a.
Eigen::Vector2d eq3(const ThermalParameters& p, const Eigen::Vector2d& x, double u, double ta) {
  const double r1 = p.r1_k_per_w, r2 = p.r2_k_per_w, c1 = p.c1_j_per_k, c2 = p.c2_j_per_k;
  return {x[1] / (r1 * c2) - x[0] * (1.0 / (r2 * c2) + 1.0 / (r1 * c2)) + ta / (c2 * r2),
          u * p.power_w / c1 + x[0] / (r1 * c1) - x[1] / (r1 * c1)};
}

// Classical fourth-order Runge–Kutta over `duration` in `steps` steps, inputs held.
Eigen::Vector2d rk4(const ThermalParameters& p, Eigen::Vector2d x, double u, double ta,
                    double duration, int steps) {
  const double h = duration / steps;
  for (int i = 0; i < steps; ++i) {
    const Eigen::Vector2d k1 = eq3(p, x, u, ta);
    const Eigen::Vector2d k2 = eq3(p, x + 0.5 * h * k1, u, ta);
    const Eigen::Vector2d k3 = eq3(p, x + 0.5 * h * k2, u, ta);
    const Eigen::Vector2d k4 = eq3(p, x + h * k3, u, ta);
    x += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  return x;
}

TEST(ThermalModel, ContinuousMatricesAreEq3) {
  const ContinuousThermalModel m = continuous_model(testing::round_thermal_parameters());
  // 1/(R2 C2) = 1/40, 1/(R1 C2) = 1/20, 1/(R1 C1) = 1/10, P/C1 = 0.6.
  EXPECT_DOUBLE_EQ(m.a(0, 0), -0.075);
  EXPECT_DOUBLE_EQ(m.a(0, 1), 0.05);
  EXPECT_DOUBLE_EQ(m.a(1, 0), 0.1);
  EXPECT_DOUBLE_EQ(m.a(1, 1), -0.1);
  EXPECT_EQ(m.b_power, Eigen::Vector2d(0.0, 0.6));
  EXPECT_EQ(m.b_ambient, Eigen::Vector2d(0.025, 0.0));
  // Agrees with the independent right-hand side at an arbitrary point.
  const Eigen::Vector2d x(23.0, 27.5);
  EXPECT_LT((m.a * x + m.b_power * 0.7 + m.b_ambient * 21.0 -
             eq3(testing::round_thermal_parameters(), x, 0.7, 21.0))
                .norm(),
            1e-12);
}

TEST(ThermalModel, EulerMatricesAreEq6) {
  const DiscreteThermalModel d = discretize_euler(testing::round_thermal_parameters(), 0.5);
  // A = [[1 − 0.5/40 − 0.5/20, 0.5/20], [0.5/10, 1 − 0.5/10]], B·P = [0, 0.5/5 · 3],
  // B′ = [0.5/40, 0].
  EXPECT_DOUBLE_EQ(d.a(0, 0), 0.9625);
  EXPECT_DOUBLE_EQ(d.a(0, 1), 0.025);
  EXPECT_DOUBLE_EQ(d.a(1, 0), 0.05);
  EXPECT_DOUBLE_EQ(d.a(1, 1), 0.95);
  EXPECT_DOUBLE_EQ(d.b_power[0], 0.0);
  EXPECT_DOUBLE_EQ(d.b_power[1], 0.3);
  EXPECT_DOUBLE_EQ(d.b_ambient[0], 0.0125);
  EXPECT_DOUBLE_EQ(d.b_ambient[1], 0.0);
  EXPECT_EQ(d.step_s, 0.5);
}

// The fast eigenvalue of Eq. 3 for the round parameters is (−0.175 − √0.010625)/2 ≈ −0.1593,
// so Euler is stable for T < 2/0.1593 ≈ 12.55 s.
TEST(ThermalModel, EulerRejectsAnUnstableStep) {
  EXPECT_NO_THROW(discretize_euler(testing::round_thermal_parameters(), 12.5));
  EXPECT_THROW(discretize_euler(testing::round_thermal_parameters(), 12.6), InvalidInput);
  EXPECT_THROW(discretize_euler(testing::round_thermal_parameters(), 0.0), InvalidInput);
}

// Each column of the exact hold is the response of Eq. 3 to a unit state or input.
TEST(ThermalModel, ZeroOrderHoldMatchesRungeKutta) {
  const ThermalParameters p = lms200_example_parameters();
  for (const double step : {1.0, 30.0, 600.0}) {
    const DiscreteThermalModel d = discretize_zoh(p, step);
    const int substeps = static_cast<int>(step * 20);
    const Eigen::Vector2d col0 = rk4(p, Eigen::Vector2d(1, 0), 0.0, 0.0, step, substeps);
    const Eigen::Vector2d col1 = rk4(p, Eigen::Vector2d(0, 1), 0.0, 0.0, step, substeps);
    const Eigen::Vector2d power = rk4(p, Eigen::Vector2d::Zero(), 1.0, 0.0, step, substeps);
    const Eigen::Vector2d ambient = rk4(p, Eigen::Vector2d::Zero(), 0.0, 1.0, step, substeps);
    EXPECT_LT((d.a.col(0) - col0).norm(), 1e-11) << step;
    EXPECT_LT((d.a.col(1) - col1).norm(), 1e-11) << step;
    EXPECT_LT((d.b_power - power).norm(), 1e-10) << step;
    EXPECT_LT((d.b_ambient - ambient).norm(), 1e-11) << step;
  }
  EXPECT_EQ(discretize_zoh(p, 0.0).a, Eigen::Matrix2d::Identity());
}

// Power step from rest: T^c(s) = P R2 / ((τ_a s + 1)(τ_b s + 1)) with τ_a τ_b = R1 R2 C1 C2 and
// τ_a + τ_b = R2 C2 + (R1 + R2) C1, so t^c − t^a = P R2 (1 − (τ_a e^{−t/τ_a} − τ_b e^{−t/τ_b}) /
// (τ_a − τ_b)).
TEST(ThermalModel, StepResponseIsTheTwoPoleSolution) {
  const ThermalParameters p = lms200_example_parameters();
  const double r1 = p.r1_k_per_w, r2 = p.r2_k_per_w, c1 = p.c1_j_per_k, c2 = p.c2_j_per_k;
  const double sum = r2 * c2 + (r1 + r2) * c1;
  const double product = r1 * r2 * c1 * c2;
  const double root = std::sqrt(sum * sum - 4.0 * product);
  const double tau_a = 0.5 * (sum + root);
  const double tau_b = 0.5 * (sum - root);
  EXPECT_NEAR(tau_a, 1829.0, 1.0);  // the ≈ 30 min case time constant
  EXPECT_NEAR(tau_b, 11.8, 0.1);    // the junction lag

  const Eigen::Index k = 7200;
  const ThermalTrajectory t =
      simulate(discretize_zoh(p, 1.0), Eigen::Vector2d(22.0, 22.0), Eigen::VectorXd::Ones(k),
               Eigen::VectorXd::Constant(k, 22.0));
  for (Eigen::Index i = 0; i < k; i += 97) {
    const double s = static_cast<double>(i);
    const double expected =
        22.0 +
        p.power_w * r2 *
            (1.0 - (tau_a * std::exp(-s / tau_a) - tau_b * std::exp(-s / tau_b)) / (tau_a - tau_b));
    EXPECT_NEAR(t.case_c[i], expected, 1e-9) << i;
  }
  // Paper scale: the case heats by a few kelvin over half an hour.
  EXPECT_NEAR(t.case_c[1800] - 22.0, 3.0, 0.2);
}

TEST(ThermalModel, EquilibriumIsTheClosedForm) {
  const ThermalParameters p = lms200_example_parameters();
  const Eigen::Vector2d on = equilibrium_state(p, 1.0, 22.0);
  EXPECT_NEAR(on[0], 22.0 + 10.0 * 0.48, 1e-12);
  EXPECT_NEAR(on[1], 22.0 + 10.0 * 0.48 + 10.0 * 0.2, 1e-12);  // 28.8 °C, as in the paper
  const double u = 0.3, ta = 19.0;
  const Eigen::Vector2d x = equilibrium_state(p, u, ta);
  const ContinuousThermalModel c = continuous_model(p);
  EXPECT_LT((c.a * x + c.b_power * u + c.b_ambient * ta).norm(), 1e-14);
  const DiscreteThermalModel d = discretize_zoh(p, 45.0);
  EXPECT_LT((d.a * x + d.b_power * u + d.b_ambient * ta - x).norm(), 1e-11);
  EXPECT_EQ(state_at_case_temperature(p, 25.0, 0.5), Eigen::Vector2d(25.0, 25.0 + 0.5 * 10 * 0.2));
}

// The rest state a case reading implies: at each power's equilibrium it is that equilibrium; a
// case at the ambient (the laser switched on from cold) has the junction at the case; the heat
// is bounded by 0 (a case below the ambient) and P (a case hotter than any power explains).
TEST(ThermalModel, TheStateFromTheCaseHeatFlowIsEachPowersEquilibrium) {
  const ThermalParameters p = lms200_example_parameters();
  for (const double u : {0.0, 0.25, 1.0}) {
    const Eigen::Vector2d at_rest = equilibrium_state(p, u, 21.0);
    EXPECT_LT((state_from_case_heat_flow(p, at_rest[0], 21.0) - at_rest).norm(), 1e-12) << u;
  }
  EXPECT_EQ(state_from_case_heat_flow(p, 21.0, 21.0), Eigen::Vector2d(21.0, 21.0));
  EXPECT_EQ(state_from_case_heat_flow(p, 19.0, 21.0), Eigen::Vector2d(19.0, 19.0));
  EXPECT_NEAR(state_from_case_heat_flow(p, 40.0, 21.0)[1], 40.0 + 10.0 * 0.2, 1e-12);
  EXPECT_THROW(state_from_case_heat_flow(p, 21.0, std::nan("")), InvalidInput);
}

// The derivation of thermal_model.hpp: a·1 + b_ambient = 1, and relative to the ambient the
// state is driven by the increments v̄_{k+1} = t^a_{k+1} − t^a_k with gain −1.
TEST(ThermalModel, AmbientEntersRelativeCoordinatesAsIncrements) {
  const ThermalParameters p = lms200_example_parameters();
  const Eigen::Index k = 500;
  Eigen::VectorXd u(k), ta(k);
  for (Eigen::Index i = 0; i < k; ++i) {
    u[i] = (i / 60) % 2 == 0 ? 1.0 : 0.0;
    ta[i] = 22.0 + 1.5 * std::sin(0.02 * static_cast<double>(i)) + 0.001 * static_cast<double>(i);
  }
  for (const DiscreteThermalModel& d : {discretize_euler(p, 2.0), discretize_zoh(p, 2.0)}) {
    EXPECT_LT((d.a * Eigen::Vector2d::Ones() + d.b_ambient - Eigen::Vector2d::Ones()).norm(),
              1e-14);
    const Eigen::Vector2d x0(24.0, 25.0);
    const ThermalTrajectory absolute = simulate(d, x0, u, ta);
    Eigen::Vector2d relative = x0 - Eigen::Vector2d::Ones() * ta[0];
    for (Eigen::Index i = 0; i < k; ++i) {
      EXPECT_NEAR(absolute.case_c[i], relative[0] + ta[i], 1e-10);
      EXPECT_NEAR(absolute.junction_c[i], relative[1] + ta[i], 1e-10);
      if (i + 1 < k) {
        relative =
            d.a * relative + d.b_power * u[i] - Eigen::Vector2d::Ones() * (ta[i + 1] - ta[i]);
      }
    }
  }
}

TEST(ThermalModel, IrregularTimesChainExactHolds) {
  const ThermalParameters p = lms200_example_parameters();
  const Eigen::VectorXd times = (Eigen::VectorXd(6) << 0.0, 1.0, 2.0, 2.0, 7.5, 100.0).finished();
  const Eigen::VectorXd u = (Eigen::VectorXd(6) << 1, 1, 0, 1, 0.5, 0).finished();
  const Eigen::VectorXd ta = (Eigen::VectorXd(6) << 22, 22.5, 23, 21, 22, 22).finished();
  const Eigen::Vector2d x0(23.0, 24.0);
  const ThermalTrajectory t = simulate_at_times(p, x0, times, u, ta);
  Eigen::Vector2d x = x0;
  for (Eigen::Index i = 0; i < 6; ++i) {
    EXPECT_NEAR(t.case_c[i], x[0], 1e-12);
    EXPECT_NEAR(t.junction_c[i], x[1], 1e-12);
    if (i + 1 < 6) x = rk4(p, x, u[i], ta[i], times[i + 1] - times[i], 4000);
  }
  // A regular grid gives the fixed-step simulation.
  const Eigen::VectorXd grid = Eigen::VectorXd::LinSpaced(6, 0.0, 50.0);
  const ThermalTrajectory fixed = simulate(discretize_zoh(p, 10.0), x0, u, ta);
  EXPECT_LT((simulate_at_times(p, x0, grid, u, ta).junction_c - fixed.junction_c).norm(), 1e-10);
}

TEST(ThermalModel, BadInputIsANamedError) {
  ThermalParameters p = lms200_example_parameters();
  p.c2_j_per_k = -1.0;
  try {
    p.validate();
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("c2_j_per_k"), std::string::npos) << e.what();
  }
  p = lms200_example_parameters();
  p.power_w = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(discretize_zoh(p, 1.0), InvalidInput);
  p = lms200_example_parameters();
  EXPECT_THROW(discretize_zoh(p, -1.0), InvalidInput);
  EXPECT_THROW(equilibrium_state(p, 1.5, 22.0), InvalidInput);
  const DiscreteThermalModel d = discretize_zoh(p, 1.0);
  const Eigen::Vector2d x0(22, 22);
  EXPECT_THROW(simulate(d, x0, Eigen::VectorXd::Ones(3), Eigen::VectorXd::Ones(2)), InvalidInput);
  EXPECT_THROW(simulate(d, x0, Eigen::VectorXd(0), Eigen::VectorXd(0)), InvalidInput);
  EXPECT_THROW(simulate(d, x0, Eigen::Vector2d(0.5, -0.1), Eigen::Vector2d(22, 22)), InvalidInput);
  EXPECT_THROW(simulate(d, x0, Eigen::Vector2d(0.5, 1), Eigen::Vector2d(22, INFINITY)),
               InvalidInput);
  EXPECT_THROW(simulate_at_times(p, x0, Eigen::Vector2d(1, 0), Eigen::Vector2d(1, 1),
                                 Eigen::Vector2d(22, 22)),
               InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
