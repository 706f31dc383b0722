// The error pass: every variant's answers against the float128 ones. See runner.hpp.

#include <cmath>

#include "runner.hpp"

namespace raykit::bench {

namespace {

/// Nearest-rank percentile of sorted values.
double percentile(const std::vector<double>& sorted, double p) {
    if (sorted.empty()) return 0;
    const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(sorted.size())));
    return sorted[std::min(sorted.size() - 1, rank == 0 ? 0 : rank - 1)];
}

void summarise(std::vector<double>& errors, double& median, double& p99, double& max) {
    std::sort(errors.begin(), errors.end());
    median = percentile(errors, 0.5);
    p99 = percentile(errors, 0.99);
    max = errors.empty() ? 0 : errors.back();
}

}  // namespace

ErrorStats sphere_errors(const Variant& v, std::size_t f, const SphereData& data) {
    ErrorStats s;
    std::vector<double> errors;
    const std::size_t n = data.family.samples.size();
    s.rays = n;
    for (std::size_t i = 0; i < n; ++i) {
        const ExactSphere& e = data.exact[i];
        if (e.near_tangent) {
            ++s.in_band;
            continue;
        }
        const Answer a = v.answer(f, i);
        if (v.kind == Kind::first_hit) {
            quad t;
            const bool hit = first_hit(e, t);
            if (hit != (a.count > 0)) {
                ++s.misclassified;
            } else if (hit) {
                ++s.compared;
                errors.push_back(ulps(t, a.t[0], v.bits));
            }
            continue;
        }
        if (e.hit != (a.count > 0)) {
            ++s.misclassified;
        } else if (e.hit) {
            ++s.compared;
            errors.push_back(std::max(ulps(e.t[0], a.t[0], v.bits), ulps(e.t[1], a.t[1], v.bits)));
        }
    }
    summarise(errors, s.median, s.p99, s.max);
    return s;
}

ErrorStats box_errors(const Variant& v, std::size_t f, const BoxData& data, const Variant* embree) {
    ErrorStats s;
    std::vector<double> errors, vs;
    const std::size_t n = data.o.size();
    s.rays = n;
    for (std::size_t i = 0; i < n; ++i) {
        const ExactBoxHit& e = data.exact[i];
        if (e.near_edge) {
            ++s.in_band;
            continue;
        }
        const Answer a = v.answer(f, i);
        const bool hit = a.count > 0;
        const bool other_rect = hit && a.rect >= 0 && a.rect != e.rect && a.rect != e.tie;
        if (hit != e.hit || other_rect) {
            ++s.misclassified;
            continue;
        }
        if (!hit) continue;
        ++s.compared;
        errors.push_back(ulps(e.t, a.t[0], 24));
        if (embree && embree != &v) {
            const Answer b = embree->answer(f, i);
            if (b.count > 0 && (b.rect == a.rect || (e.tie >= 0 && (b.rect == e.tie || b.rect == e.rect)))) {
                ++s.vs_embree_compared;
                vs.push_back(ulps(quad(b.t[0]), a.t[0], 24));  // in ulps at Embree's value
            }
        }
    }
    summarise(errors, s.median, s.p99, s.max);
    summarise(vs, s.vs_embree_median, s.vs_embree_p99, s.vs_embree_max);
    return s;
}

}  // namespace raykit::bench
