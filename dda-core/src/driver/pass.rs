//! One open-close pass: Newton-Raphson on the step's residual with the
//! contact states held, on the symmetric tangent (explicit friction, mixed
//! by Anderson, on a kept factor where it carries the iteration), then, if
//! that does not converge, on the whole tangent.

use std::time::Instant;

use rayon::prelude::*;

use super::anderson::Anderson;
use super::woodbury::{update_terms, RankOne, Woodbury};
use super::{gmres, Driver, Motion, Trial};
use crate::assembly::Change;
use crate::contact::ContactState;
use crate::error::DdaError;
use crate::solve::FactorUpdate;
use crate::system::{BlockMatrix, BlockSystem};
use crate::BLOCKS_PER_TASK;

/// Couplings (sliding contacts) up to this many are applied by the
/// Sherman-Morrison-Woodbury formula, one back-substitution each; more, by
/// GMRES on the whole tangent preconditioned by the factor at hand
/// (`PRECONDITIONED_PRODUCTS`), one back-substitution a product. GMRES
/// needs about a dozen products at 65-250 couplings, so at 64 the formula
/// spent four times what GMRES would: the 10 × 10 deformable wall shaken
/// near its sliding limit (6.5 m/s², dt 2 ms, 1 s) applied it 2,697 times
/// with 46 couplings on average, 125,000 back-substitutions beside
/// GMRES's 171,000 products. At 16 (with small factors preconditioning as
/// large ones do) that second took 8.4 s against 15.7; at 32, 11.1 s.
const SMW_COUPLINGS: usize = 16;

/// Sliding contacts up to this many are few (`RISES_BEFORE_WHOLE_TANGENT`,
/// `OWN_LARGE_FACTOR_CONTRACTION`; beyond them a pass keeps a small factor
/// as a large one, see `iterate`). At 16, as `SMW_COUPLINGS`, the shaken
/// wall above took the same time, before small factors were kept beyond
/// it (8.4 s; the rigid one 6.2 s against 6.6).
///
/// A pass counts its sliding contacts at its start, and, at a fresh
/// factor's move that raised the residual, the contacts then slipping:
/// a locked contact past its strength takes the friction's branch of the
/// return map (`ContactTerms::load`), which the symmetric tangent leaves
/// out as it does a sliding one's. A settling wall's first static pass
/// starts with every contact locked; counted by state alone, the
/// 100 × 100 deformable wall's (some 3,800 joints slipping) never reached
/// the whole tangent and climbed on fresh factors to the iteration limit:
/// 16 factorisations and a Newton failure in its settling, 2.9 s, against
/// 6 and none, 1.8 s (3D: 9 against 3, 6.7 against 4.5 s).
const FEW_SLIDING: usize = 64;

/// A step's first pass starts on the last step's factor where its matrix
/// changed by at most this share of its largest value. A rigid wall's
/// matrix changes by a spring or two a step (1.5e-4 of its largest value
/// on the 20 × 20 wall at its automatic step): a change of low rank, which
/// the mixed moves on the old factor remove, where a new factor of the
/// step's start served no better (at 1e-4 that wall factorised 95 times in
/// its first simulated second, with 345 moves; at 1e-3, 8 times with 284).
/// Where the old factor falls short, `STALE_FACTOR_MOVES` gives it up. A
/// large factor has its own limit, `LARGE_FACTOR_DRIFT`.
const FACTOR_DRIFT: f64 = 1e-3;

/// A step's first pass that started on an earlier step's factor and needed
/// more moves than this without a new one is slow; `SLOW_CARRIED_PASSES`
/// such passes in a row give that factor up, and the next step factorises
/// afresh. A change spread over the whole matrix (a deformable wall's
/// stresses as it settles) leaves the old factor a slow one: kept for
/// every later step, it cost the 20 × 20 deformable wall 242 moves instead
/// of 127 over its first 0.3 s. At 5 moves (one slow pass enough) a factor
/// that took four or five moves a step was kept for good: the 40 × 40
/// rigid wall's first second at its automatic step took 5.24 moves a
/// step, 1.83 at 3 with two passes in a row. Since a pass ends once its
/// moves have settled (`iterate`), a move sooner than its residual alone
/// would end it, such a factor takes three: at 3 that wall kept one on
/// which every pass took three moves, 2.77 a step, against 1.51 at 2; the
/// 20 × 20 deformable wall at dt 1 ms 2.37 against 1.55 (3.31 at 3 before
/// passes settled). At 3 with one pass the 20 × 20 rigid wall at its
/// automatic step went 2.68 → 3.03 moves a step (2.92 with two, 3.71 with
/// three).
const STALE_FACTOR_MOVES: usize = 2;

/// Slow passes on a carried factor (`STALE_FACTOR_MOVES`) in a row that
/// give it up.
const SLOW_CARRIED_PASSES: usize = 2;

/// `FACTOR_DRIFT` for a factor of `LARGE_FACTOR_ENTRIES` or more, which
/// costs eight to ten moves and is kept through slower ones: there a
/// looser limit only kept slow factors longer (the 40 × 40 deformable
/// wall's simulated second: 510 moves and 20 factorisations at 1e-4, 790
/// and 24 at 1e-3), so such factors keep the limit they had, and are not
/// given up after `STALE_FACTOR_MOVES` while their matrix moves (the
/// 10,051-block walls take seven moves a step on the last step's factor;
/// giving it up after five made the rigid one's step 95 → 165 ms). Once
/// it stands still (`STILL_MATRIX`) they are: a factor made then serves
/// every later step as a new one (`FACTOR_ROUND_OFF`).
const LARGE_FACTOR_DRIFT: f64 = 1e-4;

/// ... and by more than this; a matrix of `ROUND_OFF_FACTOR_ENTRIES` or
/// more that changed by no more (of its largest value) is not factorised
/// again, the factor at hand serving as a new one: the error of a move on
/// it is the change against the blocks' inertia (m/dt², which bounds the
/// matrix's smallest eigenvalue from below), and a pass's first move on it
/// is refined by one more before its residual may end the pass. A
/// standing rigid 20 × 20 wall's matrix changes by 1e-19 to 1e-11 of its
/// largest value a step (most below 1e-16): at dt 1 ms it factorised 0.94
/// times a step for nothing. Without the refining move a free cube's
/// errors of 1e-15 a step add up: spinning for a revolution, its spin
/// ended 1.4e-12 off.
const FACTOR_ROUND_OFF: f64 = 1e-12;

/// Factor entries from which a matrix changed by round-off only keeps its
/// factor (`FACTOR_ROUND_OFF`): below it (a few blocks: a free block has
/// 36 entries, the 5 × 5 rigid wall 2,187) a factorisation costs no more
/// than the move that would refine the kept factor, and a linear step
/// stays one move.
const ROUND_OFF_FACTOR_ENTRIES: usize = 1 << 12;

/// A matrix stands still where the sum of its values' changes from the
/// factor's differs from the last step's by at most this share. The
/// 40 × 40 deformable wall at its automatic step stands so from about
/// 0.3 s on, its sum the same to 3.5e-7, and took seven moves a step on a
/// factor made while it settled (6.5e-5 off it at most); given up there,
/// the next factor took two. Over its first second: 7.47 → 5.96 moves a
/// step, 13.4-13.6 → 11.9-12.8 ms (three runs alternating). Settling
/// walls' sums move by 5-20 % a step. At 1e-7 the wall did not stand
/// still; at 1e-3 the 3D 60-course rigid wall at dt 1 ms seemed to and
/// factorised once more in 20 steps, its moves 8.75 → 9.05 a step (9.80
/// at 1e-2). The largest change alone, the same from step to step
/// wherever one spring came or went since the factor, made the
/// 10,051-block 2D walls at dt 1 ms factorise 0.4 times a step (the
/// deformable one's step 94 → 161 ms).
const STILL_MATRIX: f64 = 1e-5;

/// With more sliding contacts than `FEW_SLIDING`, moves on fresh factors
/// that raise the residual this many times in a row end the symmetric
/// iteration, and the whole tangent takes over: there the symmetric one
/// climbs on to the iteration limit (a wall at a fine contact tolerance
/// spent 25 iterations and factorisations on each such pass). With fewer,
/// it runs to the limit, since its best iterate starts the whole-tangent
/// iteration, which on a wedge at its friction limit failed from an
/// earlier one. One rise, against three (two rounds alternating, first
/// 0.1 s at the automatic step): the 70 × 70 deformable wall 153 → 131
/// moves, 17 → 12 factorisations, 5.13, 4.40 → 3.55, 3.57 s; 100 × 100
/// 161 → 154 moves, the same products and factorisations, 18.2, 16.7 →
/// 16.8, 17.4 s; 70 × 70 at dt 2.3 ms 1,024 → 967 moves, 31.4, 33.8 →
/// 29.6, 33.9 s.
const RISES_BEFORE_WHOLE_TANGENT: usize = 1;

/// Whole-tangent moves with more than `SMW_COUPLINGS` couplings are
/// GMRES's on the whole tangent itself, the factor at hand
/// (the symmetric iteration's or an earlier move's) only its
/// preconditioner, kept while GMRES needs at most this many products: the
/// move is the whole tangent's whatever the factor's age. With a factor at
/// every such move, the 70 × 70 deformable wall's first 0.1 s at its
/// automatic step made 150 factorisations in 214 of them; with this, 9 in
/// 258 (2,735 products), 471–496 ms a step against 655–673. A limit of 10
/// made 36 (507 ms), one of 40 made 2, with 3,314 products (512 ms). With
/// the walls stepping at their 9.5 ms ceiling, 10 against 20 (three
/// rounds alternating, first 0.1 s): 70 × 70 deformable 378 → 269
/// products, 16 → 17 factorisations, 4.78, 4.72, 5.25 → 4.46, 4.57, 4.45
/// s; 100 × 100 891 → 591 products, 16 → 24 factorisations, 19.1, 18.1,
/// 19.2 → 17.2, 19.1, 17.6 s; the 70 × 70 at dt 2.3 and 1 ms (two rounds)
/// 36.8, 40.5 → 35.7, 30.2 s and 48.9, 60.8 → 47.8, 58.3 s. At 40, the
/// 100 × 100 wall took 1,275 products and 24.4 s.
///
/// Where the move the pass's own factor was made for needed more than
/// half as many, the factor serves while GMRES needs at most twice what it
/// needed then: its products come from the couplings, which a new factor
/// leaves as they are. On the 20 × 20 deformable wall at a hundredth of
/// the default contact tolerance, posing as large, fresh factors' moves
/// needed 12–15 products, and replacing each made 27 factorisations in 66
/// whole-tangent moves; twice, 10 in 56.
///
/// A small factor serves so too. It costs only a few products, but made
/// afresh at every such move (GMRES then on the symmetric factor's
/// x + K⁻¹USVᵀx = y), the shaken 10 × 10 wall of `SMW_COUPLINGS` made
/// 23 of its 32 factorisations a step there; so, 1.7 of 11.3.
const PRECONDITIONED_PRODUCTS: usize = 10;

/// GMRES's relative tolerance for such a move, at its tightest: an
/// inexact Newton move, as the pass's residual, not the move, decides
/// convergence. At 1e-6 the same wall made 219 such moves, 3,233 products
/// and 33 factorisations, 513–531 ms a step. Later moves of a pass take
/// `forcing`'s.
const PRECONDITIONED_TOLERANCE: f64 = 1e-3;

/// GMRES's relative tolerance at its loosest (`forcing`).
const LOOSEST_FORCING: f64 = 0.1;

/// GMRES's relative tolerance for a pass's whole-tangent move, from how
/// far the last one lowered the residual (Eisenstat and Walker 1996, their
/// second choice, 0.9 (‖Fₖ‖/‖Fₖ₋₁‖)²): while the line search keeps
/// short shares of each move the residual falls slowly and a rough
/// direction serves as well; as Newton's moves take hold the tolerance
/// tightens to `PRECONDITIONED_TOLERANCE`. A pass's first move has no
/// last one and takes the tightest. Near `target`, the residual at which
/// the pass converges, any move need only lower the residual to it: the
/// tolerance is at least half of `target` over the residual (Kelley's
/// safeguard against solving beyond the pass's own tolerance). On the
/// 70 × 70 deformable wall at its automatic step, a last move that had
/// to lower the residual 3.5 times took 10 products to 1e-3 and 4 so.
fn forcing(norm: f64, last: Option<f64>, target: f64) -> f64 {
    let fall = match last {
        Some(last) if last > 0.0 => 0.9 * (norm / last).powi(2),
        _ => 0.0,
    };
    (fall.max(0.5 * target / norm)).clamp(PRECONDITIONED_TOLERANCE, LOOSEST_FORCING)
}

/// A later pass on a large factor moves on it with at most this many
/// rank-one terms for the springs that changed since it was made
/// (`LinearSolver::update`), where more would factorise anew. Each term
/// costs a forward sweep over its blocks' path to the root of the
/// elimination tree; the 10,051-block deformable wall's factorisation
/// costs 160 ms. That wall's first 0.1 s at dt 1 ms (two passes a
/// step, one run each, with `SPRING_FLOOR_ENTRIES`'s floor): 0.17
/// factorisations a step and 292 ms at 32 terms, 0.09 and 286 ms at 48,
/// 0.01 and 267 ms at 64, the same counts and 279 ms at 96.
pub(super) const CHANGED_SPRINGS: usize = 64;

/// Factor entries from which a later pass's springs count as the factor's
/// where they changed no matrix entry by more than `LARGE_FACTOR_DRIFT` of
/// its largest (the share a step's first pass leaves to the moves on an
/// earlier step's factor); below it, only where they are the same. Some
/// 600 sliding contacts of the 10,051-block deformable wall at dt 1 ms
/// change their shear stiffness from one pass to the next with the return
/// map, so few of its later passes had as few as `CHANGED_SPRINGS` terms
/// compared exactly; with the floor, its first 0.1 s took 0.01
/// factorisations a step instead of 0.85 (11.6 million entries, 160 ms
/// each) and 19.45 moves instead of 15.15 (the later passes on the
/// factor: 8.3 moves against 3.8). The rigid one (3.0 million entries)
/// went from 0.09 factorisations and 7.89 moves a step to none and 9.10,
/// 72.7 → 77.2 ms: there the factor, refreshed by no later pass, ages.
const SPRING_FLOOR_ENTRIES: usize = 1 << 23;

/// A pass reads its contacts' open-close decisions once its residual
/// falls below this share of the step's first (where moves converge
/// linearly, on a kept factor or with explicit friction); if any contact
/// would change, the pass ends there and the next pass starts from that
/// iterate: its last digits would only refine states the next pass
/// replaces. There the 10,051-block deformable wall's iterates lie within
/// about 3e-8 w0 of the pass's answer, a third of the open-close
/// tolerance; a contact closer than that to its threshold may be decided
/// otherwise than at the answer, and costs a pass. That wall's first
/// 0.1 s at dt 1 ms (two passes a step) took 12.2 moves a step instead of
/// 19.45, with the same passes and its drift the same to 3e-14 m; at 1e-4,
/// 2.03 passes a step and the drift 2e-7 m apart. A pass on the whole
/// tangent reads them alike: where joints open one after another over a
/// step's passes, each such pass used to run on to 1e-10 (the 10,051-block
/// deformable wall at dt 1 ms with its automatic penalty, first 0.1 s:
/// 5.42 → 4.67 whole-tangent moves and 45.3 → 39.7 GMRES products a step,
/// the same passes and drift).
pub(super) const EARLY_DECISION: f64 = 1e-5;

/// A pass that has made this many moves reads its decisions early
/// (`EARLY_DECISION`) even where the recent steps took no more passes.
const SLOW_PASS_MOVES: usize = 8;

/// Whether a pass reads its contacts' decisions early (`EARLY_DECISION`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum EarlyDecision {
    /// Never: the attempt's last pass, and the one that settles a cycle,
    /// must end converged.
    Never,
    /// Once it has made `SLOW_PASS_MOVES` moves.
    IfSlow,
    /// Always: the recent attempts went on past this pass.
    Always,
}

/// The most halvings of a coupled Newton-Raphson step.
const LINE_SEARCH_HALVINGS: usize = 12;

/// A coupled step's line search starts at this many times the share of
/// its move the pass's last one kept, at most the whole move. Where a
/// pass crawls through the friction's kinks, its line searches keep
/// 1/32 to 1/2 of each move, and each halving from the whole move costs
/// an assembly; once shares grow back to a quarter, every search starts
/// at the whole move again, so Newton's last moves converge as they did.
/// The 10,051-block deformable wall's first second at its automatic
/// step: 100 → 91 whole-tangent moves, 563 → 511 GMRES products and
/// 196 → 152 line-search residuals. At 2 its first 0.1 s took more
/// whole-tangent moves (6.18 → 8.00 a step): growing only twofold, the
/// searches keep shorter moves than the kinks ask. At 8 the gain went
/// (70 × 70 wall, first 0.1 s: 4.64 whole-tangent moves a step as from
/// the whole move, 4.27 at 4).
const LINE_SEARCH_GROWTH: f64 = 4.0;

/// The largest share of the last residual that a Newton-Raphson move made
/// with an earlier iterate's factor may leave for the factor to be kept: a
/// factor costs several residual assemblies and solves, and between the
/// iterates of one pass the tangent changes only where a contact reaches
/// its strength. 0.3 kept one factor a pass on the 40 × 40 wall (0.1 took
/// two).
const KEPT_FACTOR_CONTRACTION: f64 = 0.3;

/// The same share for a factor of at least `LARGE_FACTOR_ENTRIES` entries,
/// which costs eight to ten moves (12 ms against 1.5 on the 40 × 40
/// deformable wall, 155 against 20 at 100 × 100): a kept factor that
/// contracts by 0.6 a move converges in fewer moves than that would buy.
/// Over the first ten steps at dt 1 ms, the 100 × 100 deformable wall
/// went from 0.8 factorisations and 6.9 moves a step to none and 7.8.
const KEPT_LARGE_FACTOR_CONTRACTION: f64 = 0.6;

/// The largest share of the last residual that a move on a large factor
/// of the pass's own may leave for it to be kept; beyond it the factor
/// gives way to this iterate's, kept in turn (a small one gives way to a
/// factor at every later move). A wall ringing with thousands of sliding
/// contacts contracts by 0.1-0.8 a move on fresh factors and kept ones
/// alike, the friction being explicit in both, and a large factorisation
/// costs five to eight moves: the 70 × 70 deformable wall's first 0.1 s at
/// its automatic step took 20.8 moves and 8.1 factorisations a step with a
/// factor at every move, 765 ms a step; 30.1 and 5.4 with this rule, 567
/// ms (with 1.0, a factor kept until a move raised the residual: 559 ms).
/// With no more contacts sliding than `FEW_SLIDING`, a kept move that
/// raised the residual hands the pass to the small factor's rule. The
/// wedge at FS 0.99 with stiff springs (dt 5 ms, 100 × the penalty), on
/// a solver posing as a large factor, looped without it: a fresh factor's
/// move from the best iterate rose, the kept move from there rose again
/// and was undone to the best iterate, whose factor that was; every pass
/// ran to the iteration limit and the wedge slid at 0.45 % of the Coulomb
/// rate. The small rule at every shortfall with few sliding also mended
/// it, but took the 10,051-block 3D rigid wall from 7.95 moves and no
/// factorisation a step to 9.0 and 0.1.
const OWN_LARGE_FACTOR_CONTRACTION: f64 = 0.9;

/// The share of the step's loads (`Trial::load_scale`) beyond which a
/// pass whose Newton-Raphson iteration did not converge has not solved the
/// step, and the step is cut to a third as for open-close (nearer, its
/// best iterate is kept: round-off stalls a tolerance set too fine, as on
/// the standing 10 × 10 wall at a residual tolerance of 1e-13). A block
/// at a factor of safety of 0.99 under a static step of 40 s, its inertia
/// negligible against its springs, stalled at 4.4e-4 of the loads (0.9 %
/// of its weight) with its contact locked: accepted so, it stood a whole
/// step where no balance exists. A settling step is not cut so
/// (`Driver::step`): the settling ends only in balance.
const UNSOLVED_SHARE: f64 = 1e-6;

/// Factor entries from which the large factor's rules apply (the
/// `LARGE_FACTOR_DRIFT`, `KEPT_LARGE_FACTOR_CONTRACTION` and
/// `OWN_LARGE_FACTOR_CONTRACTION` limits, exact moves where the copy's
/// fall short, a carried factor's first move in single precision): the
/// 40 × 40 deformable wall (1.3 million) and larger. Below it (the 40 × 40
/// rigid wall, 0.25 million) a factorisation costs two or three moves.
const LARGE_FACTOR_ENTRIES: usize = 1 << 20;

/// A fresh move from a pass's best iterate, as far as it decides what
/// follows. With the mixing restarted, such a move and the pass's next ones
/// are a function of the iterate (its residual's norm, the same bits),
/// how it is solved, whether factors are kept, and the factor (the count
/// of factorisations, none since). A pass whose kept move from there rose
/// and was undone comes back to make it again: on the 70 × 70 deformable
/// wall at its automatic step, with 2,252 contacts sliding, the same three
/// moves came round six times to the iteration limit before the whole
/// tangent took over.
#[derive(Clone, Copy, PartialEq)]
struct FreshMove {
    norm: u64,
    precise: bool,
    keeping: bool,
    factorizations: usize,
}

impl<S: BlockSystem<N, T>, const N: usize, const T: usize> Driver<S, N, T> {
    /// Newton-Raphson on the step's residual with the contact states fixed.
    ///
    /// The symmetric tangent leaves out how a sliding contact's friction
    /// grows with its normal force; where springs are stiff against the
    /// blocks' inertia (large steps, stiff penalties) that iteration does
    /// not converge, and the step is solved again from its best iterate
    /// with the whole tangent.
    pub(super) fn newton(
        &mut self,
        dt: f64,
        masses: &[BlockMatrix<N>],
        trial: &mut Trial<T>,
    ) -> Result<(), DdaError> {
        self.cover_closed(&trial.states);
        // The entrances stay put until the pass's decision: its iterations
        // read them side by side (`chosen.rs`).
        let copying = Instant::now();
        self.chosen.update(&self.contacts, &trial.entrances);
        self.touching
            .fill(self.system.block_count(), &self.contacts);
        self.stats.times.assembly += copying.elapsed();
        let solved = self.solve_pass(dt, masses, trial);
        self.touching.clear();
        solved
    }

    /// The pass's iterations: on the symmetric tangent, then, if those do
    /// not converge and contacts slide (or more than `FEW_SLIDING` slip
    /// locked), on the whole one.
    fn solve_pass(
        &mut self,
        dt: f64,
        masses: &[BlockMatrix<N>],
        trial: &mut Trial<T>,
    ) -> Result<(), DdaError> {
        let sliding = (trial.states.iter())
            .filter(|s| **s == ContactState::Sliding)
            .count();
        let mut hand_over = sliding > FEW_SLIDING;
        trial.solved = true;
        if self.iterate(dt, masses, trial, false, &mut hand_over)? {
            return Ok(());
        }
        if (sliding > 0 || hand_over) && self.iterate(dt, masses, trial, true, &mut false)? {
            self.stats.coupled_solves += 1;
            return Ok(());
        }
        self.stats.newton_failures += 1;
        trial.solved = trial.end_norm <= UNSOLVED_SHARE * trial.load_scale;
        Ok(())
    }

    /// Newton-Raphson iterations from `trial.d`; with `coupled`, the
    /// tangent includes friction's dependence on the normal gap (a rank-one
    /// term per sliding contact, solved by the Sherman-Morrison-Woodbury
    /// formula on the symmetric factor). Returns whether it converged;
    /// otherwise `trial.d` is left at the iterate with the smallest
    /// residual (the first one is Shi's explicit-friction solution).
    /// `hand_over`: whether a rise ends the symmetric iteration, set where
    /// it finds more than `FEW_SLIDING` contacts slipping.
    fn iterate(
        &mut self,
        dt: f64,
        masses: &[BlockMatrix<N>],
        trial: &mut Trial<T>,
        coupled: bool,
        hand_over: &mut bool,
    ) -> Result<bool, DdaError> {
        let mut first = 0.0;
        let mut residual = vec![0.0; self.matrix.dim()];
        let mut couplings = Vec::new();
        let mut best = (f64::INFINITY, trial.d.clone());
        let mut anderson = Anderson::default();
        let mut last = f64::INFINITY;
        // Whether the pass has a factor to move on; whether the last move
        // was made with an earlier iterate's factor; and whether the pass
        // still keeps factors. A step's first pass starts on the last
        // step's factor while the pattern stands and its matrix has barely
        // changed (`factor_fits`): with the same springs it carries the
        // iteration, and the test of a kept factor below refreshes it where
        // it does not (a checkpoint keeps its values, so a resumed run
        // starts on the same one). A later pass starts on its
        // own: the springs that came or went drive its first residual, and
        // an earlier pass's factor left 98-107 % of it; but on a large
        // factor, with those springs as rank-one terms where they are few
        // (`changed_springs`).
        let later = trial.load_scale > 0.0;
        // A step's first pass may move from its foreseen motion
        // (`WARM_START_MISS`). Its first assembly is still made at rest: it
        // weighs or makes the factor there, as a step started at rest
        // would, and its residual is the scale of the step's tolerance.
        let mut warm = (!later && !coupled)
            .then(|| self.warm_start.take())
            .flatten();
        let mut factored = !coupled && !later && self.analysed && self.factored.is_some();
        // Whether it starts on a large one unweighed (`weighing.rs`).
        let unweighed = factored && self.large_factor() && self.start_unweighed(dt, trial);
        let mut kept = false;
        let mut keeping = true;
        // Whether the pass keeps its own factors as a large one's pass
        // does (`KEPT_LARGE_FACTOR_CONTRACTION`,
        // `OWN_LARGE_FACTOR_CONTRACTION`): also a small one where more than
        // `FEW_SLIDING` contacts slide, since then moves contract alike on
        // fresh and kept factors, the friction being explicit in both. The
        // 10 × 10 deformable wall shaken near its sliding limit (6.5 m/s²,
        // dt 2 ms) made 327 factorisations in its first 0.25 s instead of
        // 492 with a factor at every later move; its 3D prism model's first
        // 0.3 s took 4.0 s instead of 6.2, the 20 × 20 wall's first 0.5 s
        // at the automatic step 27 s instead of 37; the 3D 20-course
        // deformable wall at rest, whose first steps slide, factorised 0.78
        // times a step instead of 1.61. Read at each move (below), not
        // once here: a model's first pass learns its factor's size only
        // from its first factorisation. Read here, the settling 60 × 60 3D
        // deformable wall's first pass took the small factor's rules and
        // factorised 8 times instead of once (the 100 × 100 one 23 times
        // instead of 9, 15 s against 7.4).
        let (mut stale, drift) = if self.large_factor() {
            (usize::MAX, LARGE_FACTOR_DRIFT)
        } else {
            (STALE_FACTOR_MOVES, FACTOR_DRIFT)
        };
        let mut rises = 0;
        // The last Newton move's largest entry (`settled` below), and the
        // largest a move may be to end a pass.
        let mut last_move = f64::INFINITY;
        let increment = self.settings.increment_tolerance * self.length_scale;
        // Whether the pass's moves are solved exactly, and whether the last
        // one was solved inexactly (see below).
        let (mut exact, mut inexact) = (false, false);
        let mut moves = 0;
        // Whether a whole-tangent move may run on the factor at hand
        // (`PRECONDITIONED_PRODUCTS`).
        let mut precondition = true;
        // The products of the first such move on the pass's own factor
        // (`PRECONDITIONED_PRODUCTS`).
        let mut fresh_products = 0;
        // The residual at the pass's last whole-tangent move (`forcing`).
        let mut coupled_norm = None;
        // Whether the pass runs on an earlier step's factor (until it
        // factorises anew).
        let mut carried = false;
        // Whether the pass's first move was made on a factor whose matrix
        // has changed by round-off since (`FACTOR_ROUND_OFF`): its residual
        // is refined by one more move, not taken as converged, so a linear
        // step is solved to round-off as on a new factor.
        let mut refine = false;
        // Where the pass last made a fresh move from its best iterate (see
        // `FreshMove`).
        let mut fresh_from = None;
        // The springs changed since the factor was made, applied to its
        // moves (a later pass's, see `CHANGED_SPRINGS`).
        let mut changed: Option<FactorUpdate> = None;
        // Whether the pass has read its decisions (`EARLY_DECISION`), or
        // will not.
        let mut decided = self.early_decision == 0.0;
        // The share of its move the last coupled step kept
        // (`LINE_SEARCH_GROWTH`).
        let mut kept_share = 1.0_f64;
        for iteration in 0..=self.settings.newton_limit {
            couplings.clear();
            // How the matrix just assembled differs from the factor's, where
            // already read (a step's first assembly): a factorisation of it
            // in this iteration need not read it again.
            let mut measured = None;
            // The tangent is assembled where a new factor is sure to be
            // needed, and at a pass's start to weigh the last step's factor
            // against it (unless the step starts on it unweighed);
            // elsewhere only if the kept one falls short.
            let tangent = coupled || !keeping || !factored || (iteration == 0 && !unweighed);
            if iteration == 0 && unweighed {
                // The springs recorded as the factor's, as where it fits.
                self.load(dt, masses, trial, &mut residual, None, Motion::Springs);
            } else {
                self.assemble(
                    dt,
                    masses,
                    trial,
                    &mut residual,
                    coupled.then_some(&mut couplings),
                    tangent,
                );
            }
            if iteration == 0 && factored {
                let still;
                if unweighed {
                    still = false;
                } else {
                    (factored, still, measured) = self.factor_fits(drift);
                    if self.large_factor() {
                        let share =
                            measured.map_or(f64::INFINITY, |c| c.largest / (drift * c.scale));
                        self.weighed(dt, trial, share, factored && !still);
                    }
                }
                carried = factored;
                if still {
                    stale = STALE_FACTOR_MOVES;
                }
                if factored {
                    self.record_springs(trial);
                }
            }
            if iteration == 0 && later && !coupled && self.analysed && self.factored.is_some() {
                changed = self.changed_springs(trial);
                factored = changed.is_some();
                carried = factored;
            }
            if residual.iter().any(|v| !v.is_finite()) {
                return Err(DdaError::NotFinite {
                    time: self.load_time(dt),
                });
            }
            let norm = residual.iter().map(|r| r * r).sum::<f64>().sqrt();
            trial.end_norm = norm;
            if iteration == 0 && !later {
                trial.rest_norm = norm;
            }
            if iteration == 0 {
                // A later pass starts from the last one's solution, so its
                // residual is only what the changed states add: measured
                // against that alone, it would be solved to many more
                // digits than the step's first pass was.
                trial.load_scale = trial.load_scale.max(norm);
                first = trial.load_scale;
            }
            if norm < best.0 {
                best.0 = norm;
                best.1.clone_from(&trial.d);
            }
            // A move on a kept factor leaves an error about its residual's
            // contraction ρ times the last: the moves still to come would
            // add up to about the last one times ρ / (1 − ρ). Where that is
            // below the increment tolerance, they would only balance stiff
            // springs' forces to digits no displacement shows: on the
            // 20 × 20 deformable wall at dt 1 ms, 692 of the 1,000 passes
            // of its first second made a last move of 1e-22 to 5e-15 w0 to
            // take the residual from 1e-8–1e-10 of the step's first to the
            // tolerance.
            let settled =
                kept && !refine && norm < last && last_move * norm / (last - norm) <= increment;
            let converged = settled
                || (iteration > 0 && !refine && norm <= self.settings.residual_tolerance * first);
            let early = match self.decide_early {
                EarlyDecision::Never => false,
                EarlyDecision::IfSlow => moves >= SLOW_PASS_MOVES,
                EarlyDecision::Always => true,
            };
            if !converged
                && !decided
                && early
                && iteration > 0
                && norm <= self.early_decision * first
            {
                decided = true;
                if self.decisions_change(trial, dt) {
                    self.stats.early_decisions += 1;
                    self.stats.whole_tangent_early_decisions += usize::from(coupled);
                    if carried {
                        self.carried_pass_ended(moves > stale);
                    }
                    return Ok(true);
                }
            }
            refine = false;
            rises = if !kept && norm > last { rises + 1 } else { 0 };
            if rises > 0 && !*hand_over && !coupled {
                *hand_over = self.slipping() > FEW_SLIDING;
            }
            let diverging = !kept
                && (norm > 1e3 * best.0 || (*hand_over && rises >= RISES_BEFORE_WHOLE_TANGENT));
            if converged || diverging || iteration == self.settings.newton_limit {
                if carried {
                    self.carried_pass_ended(moves > stale);
                }
                if !converged {
                    trial.d = best.1;
                    trial.end_norm = best.0;
                }
                return Ok(converged);
            }
            // A small kept factor that does not carry the iteration (a
            // contact's force reached or left its strength) gives way to
            // this iterate's own tangent, and so does every later one of
            // the pass: where the tangent changes from one iterate to the
            // next, moves on an old one only spend the iteration limit. A
            // large one (or any, where many contacts slide) gives way more
            // sparingly, unless few contacts slide and its move rose
            // (`OWN_LARGE_FACTOR_CONTRACTION`). A kept factor's
            // move that raised the residual is undone: the next move is
            // Newton's from the best iterate.
            let keeps_as_large = self.large_factor() || *hand_over;
            let give_way = if keeps_as_large {
                KEPT_LARGE_FACTOR_CONTRACTION
            } else {
                KEPT_FACTOR_CONTRACTION
            };
            if kept && norm > give_way * last {
                if inexact && self.large_factor() {
                    // The move may have fallen short by the single-precision
                    // copy's round-off, not the factor's age: near the
                    // tolerance a large 3D wall's moves stall on the copy,
                    // and a new factor's, solved on its copy again, stall
                    // alike. A large factorisation costs many moves, so the
                    // pass's later moves are solved exactly (on this factor
                    // and any that replaces it); only if one of those falls
                    // short does this one give way.
                    exact = true;
                } else if carried {
                    // An earlier step's factor is replaced once, by this
                    // iterate's; the pass's own falls short only where the
                    // tangent changes from one iterate to the next.
                    factored = false;
                } else if !keeps_as_large || (!*hand_over && norm > last) {
                    keeping = false;
                } else if norm > OWN_LARGE_FACTOR_CONTRACTION * last {
                    factored = false;
                }
                if norm > last {
                    trial.d.clone_from(&best.1);
                    trial.end_norm = best.0;
                    kept = false;
                    last = best.0;
                    anderson.restart();
                    continue;
                }
            }
            let preconditioned = coupled && couplings.len() > SMW_COUPLINGS;
            let refresh = if coupled {
                !(preconditioned && precondition && self.factored.is_some())
            } else {
                !keeping || !factored
            };
            if norm > last || (kept && refresh) {
                // A mixed move that did not lower the residual (a contact
                // crossed its strength), or a new factor: mix again from
                // here.
                anderson.restart();
            }
            // A fresh move from the best iterate that the pass made before,
            // on the same factor, would repeat the moves since to the
            // iteration limit: the pass ends here, at its best iterate, as
            // it would there.
            let from_best = (refresh && !coupled && norm == best.0)
                .then(|| FreshMove {
                    norm: norm.to_bits(),
                    precise: exact || moves == 0,
                    keeping,
                    factorizations: self.stats.factorizations,
                })
                .filter(|_| anderson.is_empty() && trial.d == best.1);
            if from_best.is_some() && from_best == fresh_from {
                return Ok(false);
            }
            last = norm;
            self.stats.newton_iterations += 1;
            if refresh {
                if !tangent {
                    self.assemble(dt, masses, trial, &mut residual, None, true);
                }
                let before = self.stats.factorizations;
                refine = !self.factorize(measured.filter(|_| tangent))? && moves == 0;
                self.record_springs(trial);
                changed = None;
                if coupled {
                    self.stats.whole_tangent_factorizations += self.stats.factorizations - before;
                }
                carried = false;
                factored = true;
                fresh_from = from_best.map(|f| FreshMove {
                    factorizations: self.stats.factorizations,
                    ..f
                });
            }
            if let Some(start) = warm.take() {
                // The first move is made from the foreseen motion, on the
                // residual there (the forces alone). With the factor weighed
                // there too, the 40 × 40 deformable wall at dt 1 ms and its
                // automatic penalty gave it up more often: 2.12
                // factorisations a step, against 1.89 started at rest and
                // 1.85 weighed at rest.
                trial.d = start;
                self.stats.warm_starts += 1;
                self.load(dt, masses, trial, &mut residual, None, Motion::Implicit);
                let norm = residual.iter().map(|r| r * r).sum::<f64>().sqrt();
                trial.end_norm = norm;
                if norm < best.0 {
                    best.0 = norm;
                    best.1.clone_from(&trial.d);
                }
                last = norm;
            }
            // A whole-tangent move is Newton's on any factor.
            kept = !refresh && !coupled;
            let solving = Instant::now();
            // A pass's first move is solved exactly: where the equations
            // are linear it is the answer. Later ones correct an iterate of
            // a tangent that is itself approximate (explicit friction, a
            // kept factor), so single precision costs them nothing, until
            // what is left is its round-off (above). So does the first move
            // on an earlier step's large factor: the matrix has changed
            // since, and the 10,051-block deformable wall's such moves
            // leave 1e-5 of the residual against single precision's 3e-7;
            // its solve is the pass's dearest. A small factor's is cheap,
            // and its round-off only tips residuals that land at the
            // tolerance across it.
            let first_exact = !(carried && self.large_factor());
            // A preconditioned whole-tangent move's GMRES makes it exact
            // to its own tolerance.
            let precise = if coupled {
                !preconditioned
            } else {
                exact || (moves == 0 && first_exact)
            };
            inexact = !precise && self.solver.corrections_inexact();
            match &changed {
                Some(update) => self.solver.solve_updated(update, &mut residual, precise),
                None if precise => self.solver.solve(&mut residual),
                None => self.solver.solve_correction(&mut residual),
            }
            moves += 1;
            if coupled {
                self.stats.whole_tangent_moves += 1;
            }
            if !couplings.is_empty() {
                let target = self.settings.residual_tolerance * first;
                let tolerance = forcing(norm, coupled_norm, target);
                coupled_norm = Some(norm);
                let (solved, products) =
                    self.correct(&couplings, &mut residual, preconditioned, tolerance);
                self.stats.whole_tangent_products += products;
                if refresh {
                    fresh_products = products;
                }
                precondition =
                    solved && products <= PRECONDITIONED_PRODUCTS.max(2 * fresh_products);
            }
            self.stats.times.solve += solving.elapsed();
            self.stats.count_solves(self.solver.take_counts());
            // Convergence is read off the Newton move itself: a mixed or
            // shortened move can be tiny where the residual is not.
            let newton_move = residual.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
            last_move = newton_move;
            if !coupled {
                anderson.mix(&mut residual);
            }
            if !couplings.is_empty() {
                // The friction's direction turns fast with the stretch, so
                // a full step can overshoot: halve it until the residual
                // falls (the exact tangent makes the step a descent one).
                let step = std::mem::take(&mut residual);
                let start = trial.d.clone();
                let mut scale = (LINE_SEARCH_GROWTH * kept_share).min(1.0);
                let mut probe = vec![0.0; step.len()];
                for _ in 0..LINE_SEARCH_HALVINGS {
                    for (i, (d, d0)) in trial
                        .d
                        .chunks_exact_mut(N)
                        .zip(start.chunks_exact(N))
                        .enumerate()
                    {
                        let dd = self.matrix.block(&step, i);
                        for ((d, d0), dd) in d.iter_mut().zip(d0).zip(dd.iter()) {
                            *d = d0 + scale * dd;
                        }
                    }
                    self.assemble(dt, masses, trial, &mut probe, None, false);
                    self.stats.line_search_residuals += 1;
                    let trial_norm = probe.iter().map(|r| r * r).sum::<f64>().sqrt();
                    if trial_norm < (1.0 - 1e-4 * scale) * norm {
                        break;
                    }
                    scale *= 0.5;
                }
                trial.d = start;
                kept_share = scale;
                residual = step.iter().map(|dd| dd * scale).collect();
            }
            // On every core; the largest entry is the same in any order.
            let matrix = &self.matrix;
            let largest = (trial.d.par_chunks_exact_mut(N).enumerate())
                .with_min_len(BLOCKS_PER_TASK)
                .map(|(i, d)| {
                    let mut largest: f64 = 0.0;
                    for (d, dd) in d.iter_mut().zip(matrix.block(&residual, i).iter()) {
                        *d += dd;
                        largest = largest.max(dd.abs());
                    }
                    largest
                })
                .reduce(|| 0.0, f64::max);
            if !largest.is_finite() {
                return Err(DdaError::NotFinite {
                    time: self.load_time(dt),
                });
            }
            // A kept factor stiffer than the tangent makes short moves
            // that are no sign of convergence.
            if !kept && newton_move <= increment {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Turns `y = K⁻¹r` (K the symmetric tangent) into the solution with
    /// K + Σ sⱼ uⱼvⱼᵀ: x = y − Z (I + S VᵀZ)⁻¹ S Vᵀy, with Z = K⁻¹U; where
    /// `preconditioned` (beyond `SMW_COUPLINGS` couplings), by GMRES on
    /// F⁻¹(K + U S Vᵀ)x = y with y = F⁻¹r, F the factor at hand (solved in
    /// single precision where it has a copy), to `tolerance`. Returns
    /// whether GMRES reached its tolerance, and its products.
    fn correct(
        &self,
        couplings: &[RankOne<N>],
        y: &mut [f64],
        preconditioned: bool,
        tolerance: f64,
    ) -> (bool, usize) {
        // out += Σ sⱼuⱼ(vⱼᵀv).
        let couple = |v: &[f64], out: &mut [f64]| {
            for c in couplings {
                let w = c.slope * c.dot(&self.matrix, v);
                self.matrix.add_block(out, c.blocks[0], &(c.u[0] * w));
                self.matrix.add_block(out, c.blocks[1], &(c.u[1] * w));
            }
        };
        if preconditioned {
            let mut products = 0;
            let apply = |v: &[f64], out: &mut [f64]| {
                products += 1;
                self.matrix.multiply_into(v, out);
                couple(v, out);
                self.solver.solve_correction(out);
            };
            let rhs = y.to_vec();
            let solved = gmres::gmres(apply, &rhs, y, tolerance, 60);
            return (solved, products);
        }
        Woodbury::new(couplings.to_vec(), &self.matrix, &*self.solver).apply(&self.matrix, y);
        (true, 0)
    }

    /// Whether any contact's decision at the trial would change its state
    /// or entrance; if so the decisions stay read for the pass's
    /// `decide`, which follows at the same trial.
    fn decisions_change(&mut self, trial: &Trial<T>, dt: f64) -> bool {
        let deciding = Instant::now();
        let decisions = self.decisions_at(trial, dt, &trial.d);
        let change = decisions.iter().any(|d| d.changed);
        self.decisions = decisions;
        self.decisions_read = change;
        self.stats.times.open_close += deciding.elapsed();
        change
    }

    /// The springs by which the tangent just assembled differs from the
    /// factor's matrix, ready to apply to its moves, where the factor is
    /// large and they are few (`CHANGED_SPRINGS`); on a factor of
    /// `SPRING_FLOOR_ENTRIES` or more, only those that changed a matrix
    /// entry by more than `LARGE_FACTOR_DRIFT` of the factor's largest,
    /// the share a step's first pass leaves to the moves on an earlier
    /// step's factor.
    fn changed_springs(&mut self, trial: &Trial<T>) -> Option<FactorUpdate> {
        if !self.large_factor() || self.changed_springs == 0 {
            return None;
        }
        let started = Instant::now();
        let terms = self.factor_springs.changed(
            &self.contact_loads,
            &trial.entrances,
            &self.contacts,
            &self.chosen,
            self.changed_springs,
            self.changed_floor(),
        )?;
        let update = self.solver.update(&update_terms(&terms, &self.matrix));
        self.stats.times.solve += started.elapsed();
        self.stats.changed_spring_passes += usize::from(update.is_some());
        update
    }

    /// The factor now holds the springs of the last tangent assembly; kept
    /// only where later passes may move on it (a large factor), as the
    /// record copies every contact's springs.
    fn record_springs(&mut self, trial: &Trial<T>) {
        if self.large_factor() && self.changed_springs > 0 {
            (self.factor_springs).record(&self.contact_loads, &trial.entrances);
        } else {
            self.factor_springs.forget();
        }
    }

    /// How far a spring may change a matrix entry and still count as the
    /// factor's (`SPRING_FLOOR_ENTRIES`), of the factor's matrix's largest
    /// value (read off its values once a later pass: 1.4 million at
    /// 10,051 deformable blocks).
    fn changed_floor(&self) -> f64 {
        match &self.factored {
            Some(values) if self.solver.factor_entries() >= SPRING_FLOOR_ENTRIES => {
                LARGE_FACTOR_DRIFT * values.iter().fold(0.0, |m: f64, v| m.max(v.abs()))
            }
            _ => 0.0,
        }
    }

    /// A pass on an earlier step's factor has ended, `slow` or not
    /// (`STALE_FACTOR_MOVES`): the factor is given up after
    /// `SLOW_CARRIED_PASSES` slow ones in a row.
    fn carried_pass_ended(&mut self, slow: bool) {
        self.slow_carried = if slow { self.slow_carried + 1 } else { 0 };
        if self.slow_carried >= SLOW_CARRIED_PASSES {
            self.factored = None;
            self.slow_carried = 0;
        }
    }

    /// Closed contacts on their friction's branch at the last assembly of
    /// their loads (`ContactLoad::slipping`).
    fn slipping(&self) -> usize {
        (self.contact_loads.par_iter())
            .filter(|l| l.is_some_and(|l| l.slipping))
            .count()
    }

    /// Whether the solver's factor is large (`LARGE_FACTOR_ENTRIES`), read
    /// at the moment: a run's first pass starts with none.
    fn large_factor(&self) -> bool {
        self.solver.factor_entries() >= LARGE_FACTOR_ENTRIES
    }

    /// Whether the step may start on the last factor: its matrix changed
    /// (largest change against largest value) by more than round-off and
    /// at most `drift` (`FACTOR_DRIFT`, or `LARGE_FACTOR_DRIFT` for a large
    /// factor) from the one just assembled; and whether the matrix stands
    /// still (`STILL_MATRIX`); and the change read.
    fn factor_fits(&mut self, drift: f64) -> (bool, bool, Option<Change>) {
        let Some(old) = &self.factored else {
            return (false, false, None);
        };
        // Read off the matrix's blocks: the values are gathered only for a
        // factorisation.
        let Some(change) = self.matrix.change_from(old) else {
            return (false, false, None);
        };
        let still = (self.factor_change)
            .is_some_and(|last| (change.total - last).abs() <= STILL_MATRIX * change.total);
        self.factor_change = Some(change.total);
        let fits = change.largest > FACTOR_ROUND_OFF * change.scale
            && change.largest <= drift * change.scale;
        (fits, still, Some(change))
    }

    /// Factorizes the assembled matrix unless its values changed by
    /// round-off only (`FACTOR_ROUND_OFF`, `ROUND_OFF_FACTOR_ENTRIES`).
    /// `measured`: the matrix's change from the factor's, where already
    /// read. Returns whether the factor is exactly the matrix's.
    fn factorize(&mut self, measured: Option<Change>) -> Result<bool, DdaError> {
        self.matrix.values_into(&mut self.values);
        if self.values.iter().any(|v| !v.is_finite()) {
            return Err(DdaError::NotFinite { time: self.time });
        }
        if !self.analysed {
            let started = Instant::now();
            self.solver.analyse(&self.matrix.pattern())?;
            self.analysed = true;
            self.factored = None;
            self.stats.symbolic_analyses += 1;
            self.stats.times.symbolic += started.elapsed();
        }
        let large = self.solver.factor_entries() >= ROUND_OFF_FACTOR_ENTRIES;
        let change = (self.factored.as_ref())
            .and_then(|old| measured.or_else(|| self.matrix.change_from(old)))
            .filter(|c| c.largest == 0.0 || (large && c.largest <= FACTOR_ROUND_OFF * c.scale));
        if change.is_none() {
            let started = Instant::now();
            self.solver.factorize(&self.values)?;
            self.stats.times.numeric += started.elapsed();
            self.stats.factorizations += 1;
            self.factor_change = None;
            // The factored values swap places with the buffer the next
            // assembly fills: no copy, no allocation.
            let spare = self.factored.take().unwrap_or_default();
            self.factored = Some(std::mem::replace(&mut self.values, spare));
        }
        Ok(change.is_none_or(|c| c.largest == 0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tolerance follows the residual's last fall, squared, between
    /// its bounds: a pass's first move and a fast fall take the tightest,
    /// a slow fall the loosest. Far from the pass's target it is read off
    /// the fall alone; near it, a move need only reach the target.
    #[test]
    fn forcing_follows_the_residuals_fall() {
        let far = 1e-12;
        assert_eq!(forcing(1.0, None, far), PRECONDITIONED_TOLERANCE);
        assert_eq!(forcing(1e-3, Some(1.0), far), PRECONDITIONED_TOLERANCE);
        assert_eq!(forcing(0.9, Some(1.0), far), LOOSEST_FORCING);
        assert!((forcing(0.2, Some(1.0), far) - 0.036).abs() < 1e-15);
        assert_eq!(forcing(1.0, Some(0.0), far), PRECONDITIONED_TOLERANCE);
        // A residual four times its target: the move need lower it by
        // four, not by a thousand (half of a quarter, held at the loosest).
        assert_eq!(forcing(4e-9, Some(1e-6), 1e-9), LOOSEST_FORCING);
        assert_eq!(forcing(4e-9, None, 1e-9), LOOSEST_FORCING);
        // Twenty times: half of a twentieth.
        assert!((forcing(2e-8, Some(1e-6), 1e-9) - 0.025).abs() < 1e-15);
        // Far above it, the fall's.
        assert_eq!(forcing(1e-5, Some(1e-2), 1e-9), PRECONDITIONED_TOLERANCE);
    }
}
