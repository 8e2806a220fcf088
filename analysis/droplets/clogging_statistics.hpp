// clogging_statistics.hpp — statistics of clogging in an ensemble of replicas (capillary-droplets
// §4.2, eq. 16): the probability P(r) that a droplet travels farther than r before it clogs, and
// the clogging decay length λ of P(r) = exp(−r/λ), estimated by maximum likelihood from replicas
// that clogged (their distance is known) and replicas that never clogged before the run ended
// (right-censored: only a lower bound on their distance is known).
#pragma once

#include <vector>

namespace mesoflow::droplets {

// One replica: the distance travelled, and whether the run ended by clogging there (false: the
// run hit its time limit with the droplet still moving, so the distance is a lower bound).
struct ReplicaOutcome {
  double distance;
  bool clogged;
};

// λ̂ and its likelihood-ratio confidence interval. For exponential data with right censoring the
// log-likelihood is ℓ(λ) = −k ln λ − T/λ (k clogged replicas, T the total distance of all
// replicas), so λ̂ = T/k; the interval is {λ : 2[ℓ(λ̂) − ℓ(λ)] ≤ χ²₁(level)}. With no clogged
// replica λ̂ is infinite and only the lower bound T/(χ²₁/2) is finite (upper = +inf).
struct DecayLengthEstimate {
  double lambda;
  double lower;
  double upper;
  int clogged;
  int censored;
  double total_distance;
};

// level: confidence level in (0, 1), e.g. 0.95. Throws std::invalid_argument for an empty ensemble,
// negative or non-finite distances, or a level outside (0, 1).
DecayLengthEstimate decay_length(const std::vector<ReplicaOutcome>& outcomes, double level = 0.95);

// Kaplan–Meier estimate of P(r): the survival curve as (distance, probability) steps, one per
// distinct clogging distance, starting at (0, 1). Censored replicas leave the risk set without a
// step.
struct SurvivalPoint {
  double distance;
  double probability;
};
std::vector<SurvivalPoint> survival_curve(const std::vector<ReplicaOutcome>& outcomes);

// Quantile of the χ² distribution with one degree of freedom: χ²₁(p) = (Φ⁻¹((1 + p)/2))².
double chi_square_1_quantile(double p);

}  // namespace mesoflow::droplets
