// Whether a fit's folds shrink as its knots grow: the rule that ends a fit
// whose surface keeps folding however many knots it is given (thin arms the
// spline cannot follow, or an input that intersects itself).
//
// A round stalls the fit when it has at least kKnotGrowth times the knots
// of the round that folded least (of the rounds that fold), folds at least
// as much, and folds over at least kMinFoldedPercent of its area. Measured
// on CGAL's 58 meshes at 70 knots per round: diplodocus folded 1.32 % of
// its area at 210 knots and 2.60 % at 852 (and went on to the 50,000
// control-point cap without the rule), cactus 0.51 % at 140 and 1.20 % at
// 682, man 1.18 % at 437 and 1.60 % at 1,758; no fit that reaches its
// target stalls. The floor keeps the small folds of a coarse start out of
// it: CGAL's armadillo refined to 1.66M vertices folds 0.022 % at 70
// knots, 0.14 % at 210 and 0.039 % at 280, then down to 0.002 % over its
// next rounds (fold rounds remove folds that small).
#ifndef SDCB_CORE_FIT_FOLD_PROGRESS_H_
#define SDCB_CORE_FIT_FOLD_PROGRESS_H_

namespace sdcb {

class FoldProgress {
 public:
  static constexpr double kKnotGrowth = 4.0;
  static constexpr double kMinFoldedPercent = 0.5;

  // Records a round of `knots` knots whose surface folds over
  // `folded_area_percent` of its area; true when it stalls the fit (above).
  bool Stalls(int knots, double folded_area_percent);

  // The least folded area recorded (of the rounds that fold) and its
  // round's knots (0 before any round folded).
  double least_folded_percent() const { return least_folded_percent_; }
  int knots_at_least() const { return knots_at_least_; }

 private:
  double least_folded_percent_ = 0.0;
  int knots_at_least_ = 0;
};

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_FOLD_PROGRESS_H_
