//! Tuning: every constant of the extraction engine's heuristics, named,
//! documented and defaulted in one place (method §2). [`Tuning`] is part of
//! [`super::MeshParams`]; [`Tuning::DEFAULT`] holds the values the
//! benchmark meshes are made with. Each heuristic reads its own group.
//!
//! Angles here are in radians unless a field says otherwise. Counts of
//! steps, rip-ups and relaxations are per run.
//!
//! Constants of the standalone algorithms that other parts of the crate
//! call without a mesher stay with those algorithms: the region fill
//! ([`super::fill`]), the size field ([`super::size`]), the guard's
//! measures ([`super::guard`]) and the side test of a logical rectangle
//! ([`super::mapped`]).

use super::guard::Limits;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The extraction engine's tuning, one group per heuristic.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Tuning {
    /// The step ladder ([`super::Rung`]): budgets of the repairs and what the rungs look at.
    pub ladder: LadderTuning,
    /// The reference-point queue (thesis §5.1).
    pub queue: QueueTuning,
    /// The model's element and its remedies (method §2.4–2.6): when the model's element is taken, and how the remedies are built.
    pub choice: ChoiceTuning,
    /// Transitions: the 3-to-1 template that coarsens a row.
    pub transition: TransitionTuning,
    /// Repairs: chord splits, squares and the tidying of a relaxed loop.
    pub repair: RepairTuning,
    /// Bridges: one quad across a gap between two facing front edges.
    pub bridge: BridgeTuning,
    /// Closing small loops: when a skewed small loop is settled first.
    pub closure: ClosureTuning,
    /// Mapped grids on narrow logical rectangles and strips.
    pub mapped: MappedTuning,
    /// Band closure: thin bands closed by rows along them.
    pub band: BandTuning,
    /// Corner fans: quads around a corner between a short and a long segment.
    pub fan: FanTuning,
    /// Notches: a front edge far shorter than the given segments beside it.
    pub notch: NotchTuning,
    /// The progress watch: when a run is going round in circles.
    pub watch: WatchTuning,
    /// The region fill as a step: its budget, and rewinding.
    pub fill: FillTuning,
}

impl Tuning {
    /// True when every value is the default.
    pub fn is_default(&self) -> bool {
        *self == Tuning::DEFAULT
    }

    /// The defaults.
    pub const DEFAULT: Tuning = Tuning {
        ladder: LadderTuning::DEFAULT,
        queue: QueueTuning::DEFAULT,
        choice: ChoiceTuning::DEFAULT,
        transition: TransitionTuning::DEFAULT,
        repair: RepairTuning::DEFAULT,
        bridge: BridgeTuning::DEFAULT,
        closure: ClosureTuning::DEFAULT,
        mapped: MappedTuning::DEFAULT,
        band: BandTuning::DEFAULT,
        fan: FanTuning::DEFAULT,
        notch: NotchTuning::DEFAULT,
        watch: WatchTuning::DEFAULT,
        fill: FillTuning::DEFAULT,
    };
}

impl Default for Tuning {
    fn default() -> Tuning {
        Tuning::DEFAULT
    }
}

/// The step ladder ([`super::Rung`]): budgets of the repairs and what the rungs look at.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LadderTuning {
    /// Rip-ups a run may take, plus one per [`LadderTuning::rip_up_quads`] quads made: a
    /// large domain has fronts meet in many places, each of which may need one.
    pub rip_ups: usize,
    /// See [`LadderTuning::rip_ups`].
    pub rip_up_quads: usize,
    /// Relaxations a run may take, plus one per [`LadderTuning::relax_quads`] quads made.
    pub relaxes: usize,
    /// See [`LadderTuning::relaxes`].
    pub relax_quads: usize,
    /// [`Rung::Relax`](super::Rung::Relax) is taken at most this many times in a row.
    pub relax_streak: usize,
    /// [`Rung::RipUp`](super::Rung::RipUp) removes one ring around the loop, then two, … up to
    /// this many, then one again.
    pub rip_up_rings: usize,
    /// Loops up to this many nodes are split along a chord before a square is
    /// cut on them.
    pub small_loop: usize,
    /// A stretch of the given boundary this long (nodes) that no row has
    /// reached when the queue moves on gets a row start.
    pub row_run: usize,
    /// A loop about to start a row first looks for a bridge of at least this
    /// scaled Jacobian across a gap at most [`LadderTuning::row_bridge_gap`] times as high
    /// as the edges it joins are long: a gap a row would not fit.
    pub row_bridge_sj: f64,
    /// See [`LadderTuning::row_bridge_sj`].
    pub row_bridge_gap: f64,
    /// A stuck front takes a bridge of any shape across a gap at most this
    /// many times as high as the edges it joins are long (the slanted quads
    /// of a gap between offset nodes have a scaled Jacobian of about 0.1, and
    /// no quad there does better).
    pub bridge_gap: f64,
    /// Front nodes looked at first, sharpest first, for the best rule-based
    /// element anywhere ([`Rung::Relaxed`](super::Rung::Relaxed)).
    pub sharpest: usize,
    /// The limits of [`Rung::Relaxed`](super::Rung::Relaxed) (degrees): wider than the guard's.
    pub relaxed_limits: Limits,
}

impl LadderTuning {
    /// The defaults.
    pub const DEFAULT: LadderTuning = LadderTuning {
        rip_ups: 64,
        rip_up_quads: 4096,
        relaxes: 400,
        relax_quads: 512,
        relax_streak: 3,
        rip_up_rings: 4,
        small_loop: 48,
        row_run: 4,
        row_bridge_sj: 0.5,
        row_bridge_gap: 1.0,
        bridge_gap: 0.5,
        sharpest: 32,
        relaxed_limits: Limits {
            min_corner: 10.0,
            max_corner: 170.0,
            min_front: 5.0,
        },
    };
}

impl Default for LadderTuning {
    fn default() -> LadderTuning {
        LadderTuning::DEFAULT
    }
}

/// The reference-point queue (thesis §5.1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct QueueTuning {
    /// Strategy B takes sizes within this ratio of each other as alike.
    pub band: f64,
}

impl QueueTuning {
    /// The defaults.
    pub const DEFAULT: QueueTuning = QueueTuning { band: 1.6 };
}

impl Default for QueueTuning {
    fn default() -> QueueTuning {
        QueueTuning::DEFAULT
    }
}

/// The model's element and its remedies (method §2.4–2.6): when the model's element is taken, and how the remedies are built.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ChoiceTuning {
    /// The model's element is taken at once when it scores this much.
    pub excellent: f64,
    /// The model's element is taken over a better-scoring remedy that beats
    /// it by less than this.
    pub model_margin: f64,
    /// A row's height moves towards the size field by at most this factor per
    /// element.
    pub size_step: f64,
    /// Front nodes within this many local sizes of Pn are snap candidates.
    pub snap_reach: f64,
    /// The front ahead is looked for within this many local sizes.
    pub gap_reach: f64,
    /// How far past a right-angled kite the element at a sharp corner may open
    /// its opposite corner.
    pub tip_slack: f64,
    /// The kite at a sharp corner reaches this fraction of the way to right
    /// angles beside the tip.
    pub tip_reach: f64,
    /// The kite that closes a needle (a corner whose sides are more than
    /// [`NEEDLE_RATIO`](super::guard::NEEDLE_RATIO) times the distance
    /// between their far ends) puts its new node this many such distances past
    /// the middle of that span: shallow, so the front it leaves stays smooth
    /// (about 157° at the span's ends and 203° at the new node).
    pub needle_depth: f64,
    /// A front node whose angle is above this is a row's side (below, it is a
    /// corner the row ends at).
    pub row_side: f64,
    /// ... and above this a reflex corner the row turns around.
    pub row_corner: f64,
    /// An element's corner at the node a row goes on from may differ this much
    /// from its share of the node's angle before it costs.
    pub row_slack: f64,
    /// ... and the cost grows to its floor over this much more.
    pub row_falloff: f64,
    /// The front ahead at less than this many local sizes is not split
    /// evenly by a corrected Pn (a gap of one to three sizes is).
    pub gap_min: f64,
    /// The last remedy: the rule-based Pn drawn this far from P0 towards
    /// its full height.
    pub short_rule: f64,
    /// The box of the front an evaluation reads (for the memory) reaches
    /// this many times the gap search and a local size past its points.
    pub read_margin: f64,
    /// The floor of the cost [`ChoiceTuning::row_falloff`] leads to.
    pub row_floor: f64,
}

impl ChoiceTuning {
    /// The defaults.
    pub const DEFAULT: ChoiceTuning = ChoiceTuning {
        excellent: 0.85,
        model_margin: 0.15,
        size_step: 1.1,
        snap_reach: 0.8,
        gap_reach: 2.8,
        tip_slack: 5.0 * PI / 180.0,
        tip_reach: 0.95,
        needle_depth: 0.1,
        row_side: 150.0 * PI / 180.0,
        row_corner: 225.0 * PI / 180.0,
        row_slack: 20.0 * PI / 180.0,
        row_falloff: 60.0 * PI / 180.0,
        gap_min: 0.8,
        short_rule: 0.7,
        read_margin: 1.5,
        row_floor: 0.3,
    };
}

impl Default for ChoiceTuning {
    fn default() -> ChoiceTuning {
        ChoiceTuning::DEFAULT
    }
}

/// Transitions: the 3-to-1 template that coarsens a row.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TransitionTuning {
    /// The nodes inside the stretch (`a1`, `a2`) must be this straight: their
    /// front angle within this of 180°.
    pub straight: f64,
    /// Longest over shortest of the three front edges, at most.
    pub even: f64,
    /// The row's height over the mean width, at least: a lower row would give
    /// the template flat quads.
    pub min_height: f64,
    /// Height of `m1`, `m2` as a fraction of the way from `a1`, `a2` to the top.
    pub mid: f64,
    /// The template's height moves towards the size field by at most this
    /// factor (as a row's does element by element).
    pub height_step: f64,
    /// Every quad of the template must have at least this scaled Jacobian.
    pub min_sj: f64,
    /// The guard's score of the template's outline, at least: where another
    /// front comes near, or the front left would be sharp, the row goes on
    /// with ordinary elements and the fronts meet as they would.
    pub min_score: f64,
    /// Loops shorter than this are left to the closures.
    pub min_loop: usize,
    /// Front edges either side of the stretch looked at for the top of an
    /// earlier transition. A row coarsened by transitions leaves a front of
    /// one wide edge (a template's top, carried up by the rows after it)
    /// between runs of fine ones; judged by a fine run's own edges, the rows
    /// after it would take transitions again, row after row, and coarsen far
    /// past the size field (on `disk6400` to 2–4 times the boundary's spacing
    /// inside). There the mean over the window counts instead. Twice the
    /// longest run between transitions (`k` ≈ 6 at the default ratio) always
    /// takes in a template's top; at a ratio nearer one, transitions stand
    /// further apart and `spacing_reach` looks further.
    pub spacing_reach: isize,
    /// A front edge this many times as wide as the stretch's mean is taken for
    /// the top of an earlier transition (a template's top is three times as
    /// wide as the edges it replaced). Where no such edge is near, the
    /// stretch is judged by its own edges, as on a graded front, whose edges
    /// grow far more slowly.
    pub wide: f64,
}

impl TransitionTuning {
    /// The defaults.
    pub const DEFAULT: TransitionTuning = TransitionTuning {
        straight: 30.0 * PI / 180.0,
        even: 1.6,
        min_height: 0.9,
        mid: 0.45,
        height_step: 1.1,
        min_sj: 0.4,
        min_score: 0.5,
        min_loop: 10,
        spacing_reach: 6,
        wide: 2.5,
    };
}

impl Default for TransitionTuning {
    fn default() -> TransitionTuning {
        TransitionTuning::DEFAULT
    }
}

/// Repairs: chord splits, squares and the tidying of a relaxed loop.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RepairTuning {
    /// A chord passes every front node other than its ends at least this far,
    /// as a share of the front's spacing at its ends.
    pub chord_clearance: f64,
    /// A square cut where no reference point works (`Squares::Any`) is made
    /// lower than its edge is long (0.7 or 0.5 of it) only if its sides stay
    /// at least this share of the size there. Otherwise a stuck loop's
    /// squares shrink by half at each cut, each on the side of the one before
    /// (the shortest edge), and spiral down to nothing.
    pub square_floor: f64,
    /// A removal around regions to be filled ([`Mesher::tidy_removal`]) also
    /// takes the quads at boundary edges shorter than this share of the size.
    pub tidy_edge: f64,
    /// ... and the quads at corners of the boundary sharper than this, or more
    /// reflex than a full turn less this (radians, 20°).
    pub tidy_angle: f64,
    /// See [`RepairTuning::tidy_edge`].
    pub tidy_rounds: usize,
    /// A loop is straightened only if every quad around it keeps a
    /// scaled Jacobian of at least this.
    pub relax_sj: f64,
    /// A node tidied may lower a quad around it to this scaled Jacobian
    /// (or to the quad's own, if lower).
    pub tidy_sj: f64,
    /// Loops shorter than this (nodes) are closed rather than cut by a
    /// square, except small holes no front has reached.
    pub square_min_loop: usize,
    /// The shortest front edges a square cut tries, at most.
    pub square_edges: usize,
    /// The heights a square is tried at, in edge lengths.
    pub square_heights: [f64; 3],
    /// Loops shorter than this (nodes) are not split along a chord.
    pub chord_min_loop: usize,
    /// A chord split looks at about this many ends along a loop (every
    /// node of a shorter loop, a stride along a longer one).
    pub chord_ends: usize,
    /// A chord leaves at least this angle (degrees) on each side of its ends.
    pub chord_min_part: f64,
    /// The spacing of a chord's new nodes, in the front's local edge
    /// lengths, lies in this range.
    pub chord_spacing: [f64; 2],
}

impl RepairTuning {
    /// The defaults.
    pub const DEFAULT: RepairTuning = RepairTuning {
        chord_clearance: 0.1,
        square_floor: 0.5,
        tidy_edge: 0.2,
        tidy_angle: 20.0 * PI / 180.0,
        tidy_rounds: 6,
        relax_sj: 0.2,
        tidy_sj: 0.3,
        square_min_loop: 16,
        square_edges: 64,
        square_heights: [1.0, 0.7, 0.5],
        chord_min_loop: 8,
        chord_ends: 200,
        chord_min_part: 40.0,
        chord_spacing: [0.4, 2.5],
    };
}

impl Default for RepairTuning {
    fn default() -> RepairTuning {
        RepairTuning::DEFAULT
    }
}

/// Bridges: one quad across a gap between two facing front edges.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BridgeTuning {
    /// Front edges searched for a partner around an edge, in lengths of that
    /// edge.
    pub reach: f64,
    /// The two front edges a bridge joins differ in length by at most this
    /// ratio: the two sides of a gap, not a long edge against a short one
    /// (which is a region to grade, not a gap to close).
    pub edge_ratio: f64,
    /// The guard's limits for a bridge: a gap's quads are slanted (a hole
    /// 0.05 of a spacing above the boundary, its nodes offset by half a
    /// spacing, leaves corners of 6°), and the front beside them keeps such
    /// angles until the next bridge takes them.
    pub limits: Limits,
}

impl BridgeTuning {
    /// The defaults.
    pub const DEFAULT: BridgeTuning = BridgeTuning {
        reach: 1.5,
        edge_ratio: 3.0,
        limits: Limits {
            min_corner: 2.0 * PI / 180.0,
            max_corner: 178.0 * PI / 180.0,
            min_front: 2.0 * PI / 180.0,
        },
    };
}

impl Default for BridgeTuning {
    fn default() -> BridgeTuning {
        BridgeTuning::DEFAULT
    }
}

/// Closing small loops: when a skewed small loop is settled first.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ClosureTuning {
    /// A small loop whose closure and whose nodes' quads are all at least this
    /// good (scaled Jacobian) is not settled.
    pub settled: f64,
    /// Settling never takes a quad under this (or under its own measure, if
    /// lower).
    pub settle_floor: f64,
}

impl ClosureTuning {
    /// The defaults.
    pub const DEFAULT: ClosureTuning = ClosureTuning {
        settled: 0.3,
        settle_floor: 0.1,
    };
}

impl Default for ClosureTuning {
    fn default() -> ClosureTuning {
        ClosureTuning::DEFAULT
    }
}

/// Mapped grids on narrow logical rectangles and strips.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MappedTuning {
    /// The worst quad a mapped grid may have (scaled Jacobian).
    pub min_sj: f64,
    /// The worst quad [`Mesher::close_strip`] takes on a loop with nodes
    /// extraction made (scaled Jacobian).
    pub strip_sj: f64,
    /// Loops longer than this (nodes) are not looked at: a loop is looked at
    /// again whenever it has changed, and the front of a large domain changes
    /// every step (a 4 × 196 strip is the longest mapped).
    pub max_loop: usize,
    /// A loop of the given boundary graded past
    /// [`GRADED_SPREAD`](super::mapped::GRADED_SPREAD) closes by its
    /// [`transfinite`](super::mapped::transfinite) grid when it has one,
    /// whatever its width (Gmsh's transfinite surface). Off by default:
    /// the grid's columns carry the grading across the whole domain, so
    /// where the other sides are spaced evenly its quads are slivers (a
    /// side graded 1:158 beside sides of even spacing gave 267 quads with
    /// a side ratio over 10), where extraction's corner fans and
    /// transitions coarsen the grading within a few rows.
    pub graded_grid: bool,
}

impl MappedTuning {
    /// The defaults.
    pub const DEFAULT: MappedTuning = MappedTuning {
        min_sj: 0.4,
        strip_sj: 0.2,
        max_loop: 400,
        graded_grid: false,
    };
}

impl Default for MappedTuning {
    fn default() -> MappedTuning {
        MappedTuning::DEFAULT
    }
}

/// Band closure ([`Mesher::close_band`]): a loop that is a thin band with
/// two short ends, or the ring between the front's only two loops, closed by
/// rows along it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BandTuning {
    /// The most rows a band may get (its mean width over its mean segment
    /// length, rounded); 0 turns band closure off.
    pub max_rows: usize,
    /// The most segments an end of a one-loop band may have.
    pub max_end: usize,
    /// Each node of a side lies within this many rows' spacing of the point
    /// of the other side at its own arc-length fraction (the sides face
    /// each other along the band).
    pub reach: f64,
    /// The worst quad the rows may have before smoothing (scaled Jacobian).
    pub min_sj: f64,
}

impl BandTuning {
    /// The defaults.
    pub const DEFAULT: BandTuning = BandTuning {
        max_rows: 3,
        max_end: 3,
        reach: 1.5,
        min_sj: 0.1,
    };
}

impl Default for BandTuning {
    fn default() -> BandTuning {
        BandTuning::DEFAULT
    }
}

/// Corner fans ([`super::Rung::Fan`]): a corner of the given boundary
/// between a short and a long segment takes a fan of quads around it, the
/// spokes growing evenly from one segment's length to the other's.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FanTuning {
    /// A corner whose segments' lengths differ by less than this ratio
    /// takes no fan (0: no fans at all).
    pub min_ratio: f64,
    /// The most a spoke may grow over the one before: a fan has the fewest
    /// quads that keep to it.
    pub growth: f64,
    /// The least share of the corner's angle a fan quad takes (degrees):
    /// it caps the number of quads.
    pub min_angle: f64,
    /// Corners wider than this (degrees) take no fan: a side graded along
    /// a flat stretch is for the rows.
    pub max_angle: f64,
    /// The worst quad a fan may have (scaled Jacobian); a fan with a worse
    /// one is tried with one quad fewer, down to two.
    pub min_sj: f64,
    /// Where each fan quad's far corner goes. A run that placed fans the
    /// squarest way and still needs the region fill is made again with
    /// the balanced ones ([`FillTuning::refan`]).
    pub far_corner: FarCorner,
}

/// Where a fan quad's far corner goes, among the points its two spokes
/// span ([`super::fan`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FarCorner {
    /// Where the quad's three corners other than the fan's are squarest:
    /// the best scaled Jacobian for each quad, but at a sharp corner
    /// between very unequal segments a kite whose outer side at the
    /// longer spoke is a tenth of the other, so the front leaves the long
    /// segment's end by an edge that short.
    #[default]
    Squarest,
    /// Where the worst sine of those three corners times the ratio of the
    /// quad's two outer sides (the shorter over the longer) is highest:
    /// outer sides alike, the front graded evenly from the fan, at some
    /// cost in the fan quads' own scaled Jacobian.
    Balanced,
}

impl FanTuning {
    /// The defaults.
    pub const DEFAULT: FanTuning = FanTuning {
        min_ratio: 8.0,
        growth: 2.5,
        min_angle: 10.0,
        max_angle: 150.0,
        min_sj: 0.16,
        far_corner: FarCorner::Squarest,
    };
}

impl Default for FanTuning {
    fn default() -> FanTuning {
        FanTuning::DEFAULT
    }
}

/// Notches ([`super::Rung::Notch`]): a front edge far shorter than the
/// segments of the given boundary on either side of it is cut off with
/// them by one quad, or two short edges in a row by two.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct NotchTuning {
    /// The given segments beside a notch are at least this many times as
    /// long as its short edges (0: no notches at all).
    pub min_ratio: f64,
    /// The worst quad a notch may have (scaled Jacobian).
    pub min_sj: f64,
}

impl NotchTuning {
    /// The defaults.
    pub const DEFAULT: NotchTuning = NotchTuning {
        min_ratio: 8.0,
        min_sj: 0.25,
    };
}

impl Default for NotchTuning {
    fn default() -> NotchTuning {
        NotchTuning::DEFAULT
    }
}

/// The progress watch: when a run is going round in circles.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WatchTuning {
    /// The progress watch: every [`WatchTuning::every`] steps the area the front
    /// still encloses is noted. A run whose last [`WatchTuning::window`] steps took
    /// off less than [`WatchTuning::rate`] of the mean area of its quads so far per
    /// step is going round in circles (elements cut and ripped up again, rows
    /// that grow the front where they should close it), and the region left is
    /// filled. The window is long enough for the place where the rows of a
    /// large disk meet: its rip-ups and relaxations take some 700 steps before
    /// the front closes there by itself (disk1600 finishes by extraction alone;
    /// with a window of 1,024 steps it was filled).
    ///
    /// The mean of the quads so far is not what a graded domain's fine part
    /// asks for: its quads can be a hundredth of the mean's size while the
    /// rows there move on as they should. So a run is also held to the size
    /// field: the window is no progress only if the area it took off is also
    /// under [`WatchTuning::rate`] of the area the size field asks of the quads it
    /// made (h² at each one's centre, quads later ripped up included). Knots of
    /// quads far finer than the field and rows cut and ripped up again fail
    /// both.
    pub every: usize,
    /// See [`WatchTuning::every`].
    pub window: usize,
    /// See [`WatchTuning::every`].
    pub rate: f64,
    /// The progress watch's window in the end game, when the front encloses
    /// less than one [`WatchTuning::window`] is held to take off: the last pockets
    /// where rows met close one after another, each by rip-ups and
    /// relaxations that give area back before the pocket closes, so a window
    /// sees little progress however well the run goes (disk3200 and disk4800
    /// close their last few hundred front nodes by extraction some 2,000
    /// steps after a 2,048-step window calls them stalled).
    pub end_window: usize,
    /// A window whose front lost at least this share of its nodes made
    /// progress whatever the area: pockets are closing.
    pub front_shrink: f64,
}

impl WatchTuning {
    /// The defaults.
    pub const DEFAULT: WatchTuning = WatchTuning {
        every: 128,
        window: 2048,
        rate: 0.25,
        end_window: 4 * 2048,
        front_shrink: 0.1,
    };
}

impl Default for WatchTuning {
    fn default() -> WatchTuning {
        WatchTuning::DEFAULT
    }
}

/// The region fill as a step: its budget, and rewinding.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FillTuning {
    /// Steps allowed before the region left is filled, per element a mesh
    /// following the size field would have (plus one per boundary node and
    /// 200). The size field's estimate runs low where rows cannot coarsen as
    /// fast as it asks (a fine side facing a coarse one), so the budget is
    /// three times it: at twice, a 201-against-3-node strip (`R06a`) reached
    /// it in a tangle no rewind could fill.
    pub budget: f64,
    /// A region the fill cannot take has this many element rings around it
    /// removed, one ring more at each try, before the fill gives up on it
    /// ([`Mesher::fill_rest`]).
    pub rings: usize,
    /// A mesh made by rewinding and filling whose worst quad is at least this
    /// good (scaled Jacobian, before finishing) is taken without trying earlier
    /// steps ([`Mesher::rewind_and_fill`]).
    pub rewind_good: f64,
    /// Steps a run may take (unless [`super::MeshParams::max_steps`] is set):
    /// this many per element its finest segment would make of the domain
    /// (or per boundary node, if more), plus [`FillTuning::step_limit_extra`].
    pub step_limit_per_element: usize,
    /// See [`FillTuning::step_limit_per_element`].
    pub step_limit_extra: usize,
    /// Steps the fill budget allows beyond [`FillTuning::budget`] elements
    /// and one step per boundary node.
    pub budget_extra: usize,
    /// Where a rewind goes back to, as fractions `a / b` of the steps taken,
    /// tried in order ([`FillTuning::rewind_good`]).
    pub rewind_to: [(usize, usize); 7],
    /// A fill that fails is tried again after the steps taken so far over
    /// this many, and at least [`FillTuning::retry_min`] steps.
    pub retry_share: usize,
    /// See [`FillTuning::retry_share`].
    pub retry_min: usize,
    /// Before its region fill, a run that placed corner fans with
    /// [`FarCorner::Squarest`] is made again from the start with
    /// [`FarCorner::Balanced`], and that run is taken if it finishes by
    /// extraction alone ([`Mesher::refan`]). The squarest far corners give
    /// the fan quads their best shape but leave kites at sharp corners
    /// between very unequal segments, and the rows from there can knot;
    /// the balanced ones give some quads of the fans a lower scaled
    /// Jacobian, so they are the second choice, not the first. A run the
    /// user steered (a correction, or a model set during it) is not made
    /// again.
    pub refan: bool,
}

impl FillTuning {
    /// The defaults.
    pub const DEFAULT: FillTuning = FillTuning {
        budget: 3.0,
        rings: 3,
        rewind_good: 0.2,
        step_limit_per_element: 8,
        step_limit_extra: 10_000,
        budget_extra: 200,
        rewind_to: [(3, 4), (1, 2), (1, 4), (1, 8), (1, 16), (1, 32), (0, 1)],
        retry_share: 4,
        retry_min: 50,
        refan: true,
    };
}

impl Default for FillTuning {
    fn default() -> FillTuning {
        FillTuning::DEFAULT
    }
}
