#pragma once
// How the material tangent of a point is formed, for the element-test driver and the FE solver:
// by perturbation of the integrated update (lanes of one batched update) or from the model's
// rate stiffness at the committed state.

namespace ifsim {

enum class TangentKind { perturbation, rate };

} // namespace ifsim
