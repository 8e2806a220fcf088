// capsule_record.hpp — the record of a constriction run (ConstrictionRun, capsule_runs.hpp) at
// (Ca, η) under the name <name>: the results file <name>.h5 (H5MD: the resolved parameters and the
// run's, the measures of every sample as observables, the membrane's positions every
// frame_samples() samples), the series <name>_series.csv (one row per sample: position, D_∞,Λ,
// C_f, C_r, the flow control, the step and its limits), the outlines <name>_sections.csv (the xy
// mid-plane section at the first sample with x_c ≥ 2, 3, 3.5, 4, 4.5, 5, 5.5 d), and the series the
// sweep's values are read from. The measures of a sample are analysis
// (analysis/capsule/capsule_shape.hpp), handed in by the driver.
#pragma once

#include "io/h5md_writer.hpp"
#include "scenes/capsule/capsule_runs.hpp"

#include <Eigen/Dense>

#include <array>
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <string>
#include <utility>
#include <vector>

namespace mesoflow::capsule {

template <class Real = double, class Exec = Kokkos::DefaultExecutionSpace>
class ConstrictionRecord {
 public:
  ConstrictionRecord(const ConstrictionRun<Real, Exec>& run, const std::string& name, double ca, double eta,
                     const std::vector<std::pair<std::string, std::string>>& resolved)
      : run_(run), h5_(name + ".h5") {
    for (const auto& [key, value] : resolved) h5_.set_parameter(key, value);
    const auto& scene = run.scene();
    const auto& phys = run.physical();
    const double d = phys.d, dt = run.start_dt();
    const std::pair<const char*, double> parameters[] = {
        {"ca_run", ca}, {"eta_run", eta}, {"eta_effective", run.channel().constriction_width / d},
        {"diameter_lattice", d}, {"viscosity", phys.mu}, {"surface_shear_modulus", phys.G_s}, {"k_b", phys.k_b},
        {"c0", phys.c0}, {"dt", dt}, {"surface_shear_modulus_network", phys.G_s_network},
        {"area_modulus_network", phys.K_A_network}, {"surface_shear_modulus_paper_formula", phys.G_s_paper},
        {"ca_network", phys.ca_network}, {"ca_paper_formula", phys.ca_paper}};
    for (const auto& [key, value] : parameters) h5_.set_parameter(key, value);
    h5_.set_parameter("particles", scene.num_particles());
    h5_.set_parameter("membrane_particles", scene.num_membrane());
    h5_.set_parameter("wall_particles", scene.num_walls());
    const auto& box = scene.system().box();
    h5_.add_particles_group("membrane", 3, std::size_t(scene.num_membrane()), {box.lo[0], box.lo[1], box.lo[2]},
                            {box.length[0], box.length[1], box.length[2]},
                            {box.periodic[0], box.periodic[1], box.periodic[2]});
    series_.open(name + "_series.csv");
    sections_.open(name + "_sections.csv");
    series_ << "time,x_c,x_front,x_rear,Dx,Dy,Dz,Cf,Cr,body_force,flux_ratio,max_density_deviation,dt,"
               "limit_viscous,limit_acoustic,limit_force,limit_acoustic_viscous,limit_bond\n"
            << std::setprecision(8);
    sections_ << "x_c_target,x,y\n" << std::setprecision(8);
  }

  // Records sample `s` with its measures: D = D_∞,x,y,z, C_f, C_r and the mid-plane `section`.
  void add(const ConstrictionSample& s, const std::array<double, 3>& D, double cf, double cr,
           const std::vector<Eigen::Vector2d>& section) {
    const double d = run_.physical().d;
    const auto& l = s.limits;
    series_ << s.time << "," << s.x_c / d << "," << s.x_front / d << "," << s.x_rear / d << "," << D[0] << ","
            << D[1] << "," << D[2] << "," << cf << "," << cr << "," << s.body_force << "," << s.flux_ratio << ","
            << s.density_deviation << "," << s.dt / d << "," << l.sph.viscous / d << "," << l.sph.acoustic / d
            << "," << l.sph.force / d << "," << l.sph.acoustic_viscous / d << "," << l.bond / d
            << std::endl;  // flushed: the run can be watched
    const std::int64_t s64 = s.step;
    h5_.append_observable("x_c", s64, s.time, s.x_c / d);
    h5_.append_observable("deformation_index", s64, s.time, D.data(), 3);
    const double curv[2] = {cf, cr};
    h5_.append_observable("tip_curvature_front_rear", s64, s.time, curv, 2);
    h5_.append_observable("body_force", s64, s.time, s.body_force);
    h5_.append_observable("flux_ratio", s64, s.time, s.flux_ratio);
    h5_.append_observable("max_density_deviation", s64, s.time, s.density_deviation);
    if (s.index % run_.frame_samples() == 0) {
      const auto pos = membrane_positions(run_.scene());
      h5_.append("membrane", "position", s64, s.time, pos.data(), std::size_t(run_.scene().num_membrane()), 3);
    }
    for (; next_section_ < section_targets_.size() && s.x_c / d >= section_targets_[next_section_]; ++next_section_)
      for (const auto& q : section)
        sections_ << section_targets_[next_section_] << "," << q[0] / d << "," << q[1] / d << "\n";
    xs.push_back(s.x_c / d);
    dx_s.push_back(D[0]);
    dy_s.push_back(D[1]);
    dz_s.push_back(D[2]);
    cf_s.push_back(cf);
    cr_s.push_back(cr);
  }

  void write_xdmf(const std::string& path) { h5_.write_xdmf(path); }

  std::vector<double> xs, dx_s, dy_s, dz_s, cf_s, cr_s;  // per sample: x_c/d, D_∞,x,y,z, C_f, C_r

 private:
  const ConstrictionRun<Real, Exec>& run_;
  io::H5mdWriter h5_;
  std::ofstream series_, sections_;
  const std::vector<double> section_targets_ = {2.0, 3.0, 3.5, 4.0, 4.5, 5.0, 5.5};
  std::size_t next_section_ = 0;
};

}  // namespace mesoflow::capsule
