#pragma once
// law::with_elastic_packs<L>: a contact law with the pack path of contact::face_contacts switched
// on (law::ElasticPackLaw laws only: cohesive_frictional).

#include "concepts.hpp"

namespace tessera::law {

/// Law with its elastic pack path switched on in contact::face_contacts (states stored as
/// columns, the sub-contacts whose damage flags a step leaves unchanged updated 8 per AVX-512
/// instruction; same bits as Law without FMA contraction). The named solvers of presets/pulatsu2020.hpp
/// and the examples' tie use it. With -march=native, one thread: bench_contacts' elastic prism 17.8-18.1 ns
/// per sub-contact-step against 26.0-28.8 ns; the RC tie 15.0-15.4 s against 17.1-17.5 s
/// (README, "Kernels and geometry"). Use it as the Law of contact::face_contacts:
///     solver<blocks::deformable<...>, law::with_elastic_packs<law::study_tie_law>, ...>
template <ContactLaw L>
struct with_elastic_packs : L {
  static constexpr bool use_elastic_packs = true;  ///< the elastic steps run in lane packs
};

}  // namespace tessera::law
