// stability.hpp — the explicit time-step limit of a deformable-polygon droplet, term by term.
//
// Velocity Verlet is stable for a harmonic mode of angular frequency ω while ω Δt < 2; contacts
// are nonlinear and several stiff terms act on the same vertices, so the estimate sums the squared
// frequencies of the stiffest mode of every term (an upper bound of the largest eigenvalue of the
// sum of positive semi-definite Hessians) and asks ω Δt ≤ 1. Each vertex has mass m = M/N_v.
//   wall/obstacle repulsion (capillary eq. 3): ∂²U/∂d² = 4ε_w/δ²        ⇒ ω² = 4ε_w/(δ² m)
//   line tension γP (eq. 2): a chain under tension γ, spacing l           ⇒ ω² = 4γ/(l m)
//     with l = l0/20: gravity acts on the vertices and the weak segment springs (K_l/Γ = 10⁻³)
//     let them slide down a resting droplet's interface and crowd there (edges below l0/10
//     measured at Γ = 10 in the orifice). A Γ = 10, N_v = 256 droplet held in the orifice was
//     unstable at Δt = 7.8·10⁻⁴ (the limit with l = l0), kept a numerically heated oscillation of
//     its centre at 4.6·10⁻⁴ (l0/4) and a vertex jitter E_k/E_t ~ 10⁻⁶–10⁻⁴ at rest at 3.0·10⁻⁴
//     (l0/10), and decayed steadily at 2·10⁻⁴ (docs/droplets.md).
//   segment springs k_l N_v (eq. 1): a chain of springs k_l N_v           ⇒ ω² = 4 k_l N_v/m
//   area elasticity k_a (eq. 1): rank one, k_a |∇a|², |∇a|² = Σ l_i² ≈ P l0 ⇒ ω² = k_a P l0/m
//   bending k_b (hopper eq. 8): highest mode of a discrete curvature chain ⇒ ω² = 16 k_b/(l0² m)
// Drag is first order: a vertex relaxes at the rate ν = ζ_i/(N_v m) = ζ_i/M (eqs. 5–6), largest
// at the distance floor of the near-wall term, and explicit drag wants ν Δt ≤ 1.
// DropletScene refuses a Δt above the limit and chooses min(10⁻³ t0, limit) when none is given;
// tests/dp/test_stability.cpp checks that a run at the limit stays bounded where the paper's
// parameters would blow up. The area mode depends on the shape, which a run changes:
// stability_limit_for_shape re-evaluates it on the measured shape (shape_stiffness.hpp), and
// DropletScene stops a run whose Δt the current shape no longer allows.
//
// Packings of polygons (the hopper, hopper-flows §2.3) add vertex contacts and dissipation between
// them: contact_stability_limit adds z contacts of stiffness ε_c/δ² per vertex (ω_c² = z ε_c/(δ² m),
// in quadrature with the shape modes above) and the damping rate ν = z μ/m + ζ/M of friction
// (hopper eq. 12) and uniform drag (eq. 11), with ν Δt ≤ 2 (the explicit limit of v' = −ν v at
// λ = ½); dp_hopper_scene.hpp explains z = 3.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

namespace mesoflow::dp {

struct StiffnessInputs {
  double vertex_mass;        // m = M/N_v
  double edge_length;        // l0
  double perimeter;          // P ≈ N_v l0
  double vertices;           // N_v
  double wall_energy;        // ε_w (0 without walls or obstacles)
  double vertex_diameter;    // δ
  double line_tension;       // γ
  double perimeter_stiffness;  // k_l
  double area_stiffness;     // k_a
  double bending_stiffness;  // k_b
  double max_drag;           // largest ζ_i (eq. 6 at the distance floor); M = N_v m
};

struct StabilityLimit {
  double omega_wall = 0, omega_line_tension = 0, omega_springs = 0, omega_area = 0, omega_bending = 0;
  double drag_rate = 0;  // ν = ζ_max / M
  double omega() const {
    return std::sqrt(omega_wall * omega_wall + omega_line_tension * omega_line_tension + omega_springs * omega_springs +
                     omega_area * omega_area + omega_bending * omega_bending);
  }
  // Largest Δt with ω Δt ≤ 1 and ν Δt ≤ 1 (infinite for a force-free scene).
  double max_dt() const {
    const double w = omega();
    const double by_modes = w > 0 ? 1.0 / w : HUGE_VAL;
    const double by_drag = drag_rate > 0 ? 1.0 / drag_rate : HUGE_VAL;
    return std::min(by_modes, by_drag);
  }
  // The term that sets the limit, for error messages.
  std::string limiting_term() const {
    if (drag_rate > omega()) return "near-wall drag (rate " + std::to_string(drag_rate) + "/t0)";
    const struct {
      double w;
      const char* name;
    } terms[] = {{omega_wall, "wall repulsion E_w"},
                 {omega_line_tension, "line tension Γ"},
                 {omega_springs, "perimeter elasticity K_l"},
                 {omega_area, "area elasticity K_a"},
                 {omega_bending, "bending K_b"}};
    const auto* top = std::max_element(std::begin(terms), std::end(terms),
                                       [](const auto& a, const auto& b) { return a.w < b.w; });
    return std::string(top->name) + " (ω = " + std::to_string(top->w) + "/t0)";
  }
};

constexpr double crowded_edge_fraction = 0.05;  // l/l0 for the line-tension mode (see above)

inline StabilityLimit stability_limit(const StiffnessInputs& s) {
  StabilityLimit r;
  const double m = s.vertex_mass;
  r.omega_wall = std::sqrt(4 * s.wall_energy / (s.vertex_diameter * s.vertex_diameter * m));
  r.omega_line_tension = std::sqrt(4 * s.line_tension / (crowded_edge_fraction * s.edge_length * m));
  r.omega_springs = std::sqrt(4 * s.perimeter_stiffness * s.vertices / m);
  r.omega_area = std::sqrt(s.area_stiffness * s.perimeter * s.edge_length / m);
  r.omega_bending = std::sqrt(16 * s.bending_stiffness / (s.edge_length * s.edge_length * m));
  r.drag_rate = s.max_drag / (s.vertices * m);
  return r;
}

// The limit for the current shape: the area mode with the measured largest Σ_i |∇_i a|²
// (shape_stiffness.hpp) where it exceeds the static estimate's P l0, so the result never exceeds
// stability_limit(s).
inline StabilityLimit stability_limit_for_shape(const StiffnessInputs& s, double area_gradient_squared) {
  StabilityLimit r = stability_limit(s);
  if (area_gradient_squared > s.perimeter * s.edge_length)
    r.omega_area = std::sqrt(s.area_stiffness * area_gradient_squared / s.vertex_mass);
  return r;
}

// The contacts and dissipation of a polygon packing (see the file comment).
struct ContactStiffnessInputs {
  int contacts_per_vertex;  // z
  double contact_energy;    // ε_c (contacts of stiffness ε_c/δ², δ the StiffnessInputs' vertex diameter)
  double friction;          // μ between contacting vertices
  double drag;              // ζ on the body of mass body_mass (ζ/N_v per vertex)
  double body_mass;         // M
};

struct ContactStabilityLimit {
  StabilityLimit shape;       // wall, segment, area and bending modes (stability_limit)
  double omega_contacts = 0;  // √(z ε_c/(δ² m))
  double friction_rate = 0;   // z μ/m
  double drag_rate = 0;       // ζ/M

  double omega() const { return std::sqrt(shape.omega() * shape.omega() + omega_contacts * omega_contacts); }
  double damping_rate() const { return friction_rate + drag_rate; }
  // Largest Δt with ω Δt ≤ 1 and ν Δt ≤ 2.
  double max_dt() const {
    const double w = omega(), nu = damping_rate();
    return std::min(w > 0 ? 1 / w : HUGE_VAL, nu > 0 ? 2 / nu : HUGE_VAL);
  }
  std::string limiting_term() const {
    if (damping_rate() > 2 * omega())
      return std::string(friction_rate >= drag_rate ? "friction μ" : "drag ζ") + " (damping rate " +
             std::to_string(damping_rate()) + "/t0)";
    const struct {
      double w;
      const char* name;
    } terms[] = {{shape.omega_wall, "wall repulsion E_w"},
                 {omega_contacts, "contact repulsion E_c"},
                 {shape.omega_springs, "perimeter elasticity K_l"},
                 {shape.omega_area, "area elasticity K_a"},
                 {shape.omega_bending, "bending K_b"}};
    const auto* top =
        std::max_element(std::begin(terms), std::end(terms), [](const auto& a, const auto& b) { return a.w < b.w; });
    return std::string(top->name) + " (ω = " + std::to_string(top->w) + "/t0 of a total " + std::to_string(omega()) +
           "/t0)";
  }
};

// The limit of a polygon packing: the shape modes of `s` (its max_drag is not used: drag enters
// the damping rate) plus the contacts and dissipation of `c`.
inline ContactStabilityLimit contact_stability_limit(const StiffnessInputs& s, const ContactStiffnessInputs& c) {
  ContactStabilityLimit r;
  r.shape = stability_limit(s);
  const double m = s.vertex_mass, delta = s.vertex_diameter;
  r.omega_contacts = std::sqrt(c.contacts_per_vertex * c.contact_energy / (delta * delta * m));
  r.friction_rate = c.contacts_per_vertex * c.friction / m;
  r.drag_rate = c.drag / c.body_mass;
  return r;
}

}  // namespace mesoflow::dp
