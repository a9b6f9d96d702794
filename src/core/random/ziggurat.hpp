// Internal: standard normal draws by the ziggurat method (Marsaglia & Tsang 2000, with
// Doornik's 2005 fix: the strip index and the uniform come from different bits), for noise on
// whole images, where Rng::normal's log, sqrt and cosine per draw would cost more than the
// rest of the model. 128 strips; about 98.8% of draws cost one Rng output and a multiply.
// Deterministic like Rng itself: the same generator state gives the same draws.
#pragma once

#include "epuck_vrep_compat/random/rng.hpp"

namespace evc {

// A standard normal from @p rng (one or more of its outputs).
double ziggurat_normal(Rng& rng);

}  // namespace evc
