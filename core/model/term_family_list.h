// The registered term families (term_family.h), one accessor per family,
// each defined in its own file term_family_<name>.cc. Only the registry
// (term_family.cc) includes this header; everything else reaches a family
// through FamilyOf or FamilyNamed.
//
// Thread-safety: each accessor returns a stateless function-local static.
#ifndef ROLLWEAR_CORE_MODEL_TERM_FAMILY_LIST_H_
#define ROLLWEAR_CORE_MODEL_TERM_FAMILY_LIST_H_

namespace rollwear {

class TermFamily;  // term_family.h

const TermFamily& LogLinearFamily();
const TermFamily& PowerFamily();
const TermFamily& SaturatingFamily();
const TermFamily& DecayingFamily();
const TermFamily& FlagFamily();
const TermFamily& BinnedFamily();
const TermFamily& PerLevelFamily();
const TermFamily& CellFamily();
const TermFamily& OffsetDecayFamily();
const TermFamily& OffsetLinearFamily();
const TermFamily& OffsetPerLevelFamily();
const TermFamily& OffsetBinnedFamily();
const TermFamily& RollEffectFamily();
const TermFamily& PerCoilFamily();
const TermFamily& HingeFamily();

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_TERM_FAMILY_LIST_H_
