//! The `JointedDomain` generators: a region cut into blocks by joint sets
//! (Shi's DC step), in 2D by an arrangement of joint traces
//! ([`dda_2d::cut`]), in 3D by persistent joint planes ([`dda_3d::cut`]).
//! Each set may name the law of the joints it makes; the generator reports
//! which set separates each pair of its blocks, and the law table gives
//! those pairs the set's law.

use std::ops::Not;

use dda_core::settings::{finite, non_negative, positive};
use dda_core::DdaError;
use nalgebra::{Point2, Point3, Vector2, Vector3};
use serde::{Deserialize, Serialize};

use super::{Failure, Generated, Piece};
use crate::values::{Coords, JointLaw};

/// At most this many joints from one set.
pub const MAX_JOINTS: usize = 10_000;

/// Smallest block kept by default, as a fraction of the smallest spacing
/// squared (2D) or cubed (3D).
pub const SLIVER: f64 = 1e-3;

/// One joint set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSet {
    /// Degrees below the horizontal. 2D: in (−90, 90], positive dipping
    /// toward +x (the traces run along (cos dip, −sin dip)), negative
    /// toward −x, 90 vertical. 3D: in [0, 90].
    pub dip: f64,
    /// 3D only, degrees clockwise from +y (north) toward +x (east): the
    /// direction the planes dip toward; default 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub dip_direction: f64,
    /// Distance between neighbouring joints, normal to them, m (the mean
    /// for `Random` placement); required, positive.
    pub spacing: f64,
    /// A point one joint passes through (and where trace patterns start),
    /// m; default the origin.
    #[serde(default, skip_serializing_if = "Coords::is_empty")]
    pub origin: Coords,
    /// 2D only: length of each trace, m; default none (persistent joints).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub trace_length: Option<f64>,
    /// 2D only: intact rock between traces along a joint, m; default 0.
    /// Persistence is trace_length / (trace_length + bridge).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub bridge: f64,
    /// `Regular` (default) or `Random(seed: n)`.
    #[serde(default, skip_serializing_if = "Placement::is_regular")]
    pub placement: Placement,
    /// The law of the joints this set makes; default the scene's law for
    /// the blocks' materials (`joints` by material, or `default_joint`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub law: Option<JointLaw>,
}

impl JointSet {
    /// Whether the set's own values make joints in `dimension` 2 or 3: the
    /// first field at fault and what to change. Its origin's count is
    /// checked against the scene's axes, and its law by the law, where the
    /// scene reads them.
    pub fn check(&self, dimension: u32) -> Result<(), DdaError> {
        let fail = |field, message: &str| {
            Err(DdaError::Setting {
                field,
                message: message.to_string(),
            })
        };
        let three = dimension == 3;
        let origin = self.origin.as_slice();
        origin
            .iter()
            .try_for_each(|v| finite("origin", "the origin", *v))?;
        finite("dip", "the dip", self.dip)?;
        let (lo, range) = if three {
            (0.0, "[0, 90]")
        } else {
            (-90.0, "(-90, 90]")
        };
        if self.dip < lo || self.dip > 90.0 || (!three && self.dip == -90.0) {
            let dip = self.dip;
            return fail("dip", &format!("the dip must lie in {range} degrees, got {dip}; give the angle below the horizontal"));
        }
        let hint = "give the distance between joints in m";
        positive("spacing", "the spacing", self.spacing, hint)?;
        if three {
            finite("dip_direction", "the dip direction", self.dip_direction)?;
            let planes = "3D joint sets are persistent planes; remove trace_length and bridge";
            if self.trace_length.is_some() {
                return fail("trace_length", planes);
            }
            if self.bridge != 0.0 {
                return fail("bridge", planes);
            }
        } else {
            if self.dip_direction != 0.0 {
                return fail("dip_direction", "a 2D joint set has no dip direction: a positive dip dips toward +x, a negative one toward -x; remove dip_direction");
            }
            if let Some(length) = self.trace_length {
                let hint =
                    "give the length of each trace in m, or leave it out for persistent joints";
                positive("trace_length", "the trace length", length, hint)?;
            }
            let hint = "give the intact length between traces in m";
            non_negative("bridge", "the bridge", self.bridge, hint)?;
            if self.bridge > 0.0 && self.trace_length.is_none() {
                return fail("bridge", "a bridge separates traces, but the set has no trace_length (its joints are persistent); add trace_length or remove bridge");
            }
        }
        Ok(())
    }
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// Where the joints of a set lie.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Placement {
    /// Joints exactly `spacing` apart, one through `origin`; traces start
    /// at `origin`'s projection on each joint and repeat every
    /// trace_length + bridge.
    #[default]
    Regular,
    /// Spacings drawn from a negative exponential distribution of mean
    /// `spacing` (out from `origin` both ways), and each joint's trace
    /// pattern shifted by a uniform random amount; the same `seed` gives
    /// the same joints on every machine.
    Random { seed: u64 },
}

impl Placement {
    fn is_regular(&self) -> bool {
        *self == Placement::Regular
    }
}

/// A 3D region to cut.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Region3 {
    /// The box between two opposite corners, m.
    Box { min: [f64; 3], max: [f64; 3] },
    /// The convex hull of these corners, m (4 to 64 of them).
    Hull(Vec<[f64; 3]>),
}

/// SplitMix64: small, and the same sequence everywhere.
struct Random(u64);

impl Random {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A negative exponential sample of mean `mean`.
    fn exponential(&mut self, mean: f64) -> f64 {
        -mean * (1.0 - self.next()).ln()
    }
}

impl Failure {
    fn of_set(set: usize, field: &'static str, message: String) -> Self {
        Self {
            set: Some(set),
            ..Failure::field(field, message)
        }
    }
}

fn too_many(k: usize) -> Failure {
    Failure::of_set(k, "spacing", format!("the spacing makes more than {MAX_JOINTS} joints across the region; give a larger spacing"))
}

/// The joints' distances along their normal, within (lo, hi), one at `at`
/// for regular placement; `None` beyond [`MAX_JOINTS`].
fn offsets(
    set: &JointSet,
    at: f64,
    lo: f64,
    hi: f64,
    random: &mut Option<Random>,
) -> Option<Vec<f64>> {
    let s = set.spacing;
    if !(s > 0.0 && s.is_finite()) {
        return None;
    }
    let mut out = Vec::new();
    match random {
        None => {
            let (first, last) = (((lo - at) / s).ceil(), ((hi - at) / s).floor());
            // NaN (an infinite region) fails too.
            if (last - first < MAX_JOINTS as f64).not() {
                return None;
            }
            // Counted, not stepped: far from the origin k + 1 rounds to k.
            let count = (last - first).max(-1.0) as i64 + 1;
            out.extend((0..count).map(|i| at + (first + i as f64) * s));
        }
        Some(r) => {
            // Memoryless: from the region's edge when `at` lies outside.
            let start = at.clamp(lo, hi);
            if start == at {
                out.push(at);
            }
            for dir in [1.0, -1.0] {
                let mut c = start;
                loop {
                    c += dir * r.exponential(s);
                    if !(c > lo && c < hi) {
                        break;
                    }
                    out.push(c);
                    if out.len() > MAX_JOINTS {
                        return None;
                    }
                }
            }
            out.sort_by(f64::total_cmp);
        }
    }
    out.retain(|c| *c > lo && *c < hi);
    Some(out)
}

/// The smallest block kept when none is given.
pub(crate) fn default_min_size(sets: &[JointSet], power: i32) -> f64 {
    sets.iter()
        .map(|s| s.spacing)
        .fold(f64::INFINITY, f64::min)
        .powi(power)
        .min(f64::MAX)
        * SLIVER
}

/// The sets' own values, the smallest block kept (`min`, named `field`, of
/// `what`) and the height below which blocks are fixed.
fn check(
    sets: &[JointSet],
    dimension: u32,
    min: Option<f64>,
    field: &'static str,
    what: &str,
    fixed_below: Option<f64>,
) -> Result<(), Failure> {
    for (k, set) in sets.iter().enumerate() {
        set.check(dimension).map_err(|e| Failure {
            set: Some(k),
            ..e.into()
        })?;
    }
    if let Some(v) = min {
        let hint = format!("give {what}, 0 to keep every block");
        non_negative(field, field, v, &hint)?;
    }
    if let Some(v) = fixed_below {
        finite("fixed_below", "fixed_below", v)?;
    }
    Ok(())
}

/// The set's trace direction (unit) in 2D.
fn trace_direction(dip: f64) -> Vector2<f64> {
    let (s, c) = dip.to_radians().sin_cos();
    Vector2::new(c, -s)
}

/// Cuts a 2D region; the error says what to change.
pub(crate) fn cut_2d(
    region: &[[f64; 2]],
    sets: &[JointSet],
    min_area: Option<f64>,
    fixed_below: Option<f64>,
) -> Result<Generated<[f64; 2]>, Failure> {
    let outline: Vec<Point2<f64>> = region.iter().map(|p| Point2::new(p[0], p[1])).collect();
    dda_2d::polygon::validate(&outline).map_err(|e| Failure::field("region", e.to_string()))?;
    check(
        sets,
        2,
        min_area,
        "min_block_area",
        "an area in m²",
        fixed_below,
    )?;
    let (lo, hi) = outline.iter().fold(
        (
            Point2::from([f64::INFINITY; 2]),
            Point2::from([f64::NEG_INFINITY; 2]),
        ),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    );
    let size = (hi - lo).norm();
    let mut traces = Vec::new();
    for (k, set) in sets.iter().enumerate() {
        let t = trace_direction(set.dip);
        let n = Vector2::new(-t.y, t.x);
        let origin = Vector2::new(set.origin.get(0), set.origin.get(1));
        let span = |d: &Vector2<f64>| {
            outline
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                    (a.min(d.dot(&p.coords)), b.max(d.dot(&p.coords)))
                })
        };
        let (nlo, nhi) = span(&n);
        let (tlo, thi) = span(&t);
        let (tlo, thi) = (tlo - 0.01 * size, thi + 0.01 * size);
        let mut random = match set.placement {
            Placement::Regular => None,
            Placement::Random { seed } => Some(Random(seed)),
        };
        let cs = offsets(set, n.dot(&origin), nlo, nhi, &mut random).ok_or_else(|| too_many(k))?;
        let t0 = t.dot(&origin);
        for c in cs {
            let at = |s: f64| Point2::from(n * c + t * s);
            match set.trace_length {
                None => traces.push(dda_2d::cut::Trace {
                    a: at(tlo),
                    b: at(thi),
                    set: k,
                }),
                Some(length) => {
                    let period = length + set.bridge;
                    let shift = random.as_mut().map_or(0.0, |r| r.next() * period);
                    let mut s = t0 + shift + ((tlo - t0 - shift) / period).floor() * period;
                    while s < thi {
                        traces.push(dda_2d::cut::Trace {
                            a: at(s),
                            b: at(s + length),
                            set: k,
                        });
                        s += period;
                        if traces.len() > 50 * MAX_JOINTS {
                            return Err(Failure::of_set(k, "trace_length", "the traces are too many; give a longer trace_length or a larger spacing".into()));
                        }
                    }
                }
            }
        }
    }
    let min_area = min_area.unwrap_or_else(|| default_min_size(sets, 2));
    let cut = dda_2d::cut::cut(&outline, &traces, min_area).map_err(|e| {
        let field = if matches!(e, dda_2d::cut::CutError::Region(_)) {
            "region"
        } else {
            "sets"
        };
        Failure::field(field, e.to_string())
    })?;
    if cut.blocks.is_empty() {
        return Err(Failure::field("min_block_area", format!(
            "every block is smaller than min_block_area = {min_area:e} m²; give a smaller min_block_area or wider spacings"
        )));
    }
    let tol = dda_2d::cut::SNAP * size;
    let pieces = cut
        .blocks
        .iter()
        .enumerate()
        .map(|(k, b)| Piece {
            always_fixed: fixed_below.is_some_and(|y| b.iter().all(|p| p.y <= y + tol)),
            ..Piece::new(
                Some(format!("block {k}")),
                b.iter().map(|p| [p.x, p.y]).collect(),
                Vec::new(),
            )
        })
        .collect();
    Ok(Generated {
        pieces,
        joints: cut
            .joints
            .iter()
            .map(|j| (j.blocks.0, j.blocks.1, j.set))
            .collect(),
    })
}

/// The unit normal of a 3D set's planes, pointing up.
fn plane_normal(dip: f64, dip_direction: f64) -> Vector3<f64> {
    let (sd, cd) = dip.to_radians().sin_cos();
    let (sa, ca) = dip_direction.to_radians().sin_cos();
    Vector3::new(sd * sa, sd * ca, cd)
}

/// Cuts a 3D region; the error says what to change.
pub(crate) fn cut_3d(
    region: &Region3,
    sets: &[JointSet],
    min_volume: Option<f64>,
    fixed_below: Option<f64>,
) -> Result<Generated<[f64; 3]>, Failure> {
    use dda_3d::cut::{Convex, JointPlane};
    check(
        sets,
        3,
        min_volume,
        "min_block_volume",
        "a volume in m³",
        fixed_below,
    )?;
    let convex = match region {
        Region3::Box { min, max } => Convex::cuboid(Point3::from(*min), Point3::from(*max)),
        Region3::Hull(corners) => {
            Convex::hull(&corners.iter().map(|p| Point3::from(*p)).collect::<Vec<_>>())
        }
    }
    .map_err(|e| Failure::field("region", e.to_string()))?;
    let (corners, _) = dda_3d::cut::cut(&convex, &[], 0.0)
        .map_err(|e| Failure::field("region", e.to_string()))?
        .blocks
        .remove(0);
    let (lo, hi) = corners.iter().fold(
        (
            Point3::from([f64::INFINITY; 3]),
            Point3::from([f64::NEG_INFINITY; 3]),
        ),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    );
    let mut planes = Vec::new();
    // Persistent sets cut a convex region into at most the product of
    // (joints + 1): refused before the cutting, which grows with it.
    let mut most = 1.0f64;
    for (k, set) in sets.iter().enumerate() {
        let n = plane_normal(set.dip, set.dip_direction);
        let origin = Vector3::new(set.origin.get(0), set.origin.get(1), set.origin.get(2));
        let (nlo, nhi) = corners
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(n.dot(&p.coords)), b.max(n.dot(&p.coords)))
            });
        let mut random = match set.placement {
            Placement::Regular => None,
            Placement::Random { seed } => Some(Random(seed)),
        };
        let cs = offsets(set, n.dot(&origin), nlo, nhi, &mut random).ok_or_else(|| too_many(k))?;
        most *= cs.len() as f64 + 1.0;
        if most > super::MAX_PARTS as f64 {
            return Err(Failure::of_set(k, "spacing", format!(
                "the sets would cut the region into up to {most:.3e} blocks, more than {}; give larger spacings or a smaller region",
                super::MAX_PARTS
            )));
        }
        planes.extend(cs.into_iter().enumerate().map(|(j, c)| JointPlane {
            normal: n,
            offset: c,
            set: k,
            joint: j,
        }));
    }
    let min_volume = min_volume.unwrap_or_else(|| default_min_size(sets, 3));
    let cut = dda_3d::cut::cut(&convex, &planes, min_volume)
        .map_err(|e| Failure::field("sets", e.to_string()))?;
    if cut.blocks.is_empty() {
        return Err(Failure::field("min_block_volume", format!(
            "every block is smaller than min_block_volume = {min_volume:e} m³; give a smaller min_block_volume or wider spacings"
        )));
    }
    let tol = dda_3d::cut::SNAP * (hi - lo).norm();
    let pieces = cut
        .blocks
        .into_iter()
        .enumerate()
        .map(|(k, (v, faces))| Piece {
            always_fixed: fixed_below.is_some_and(|z| v.iter().all(|p| p.z <= z + tol)),
            ..Piece::new(
                Some(format!("block {k}")),
                v.iter().map(|p| [p.x, p.y, p.z]).collect(),
                faces,
            )
        })
        .collect();
    Ok(Generated {
        pieces,
        joints: cut
            .joints
            .iter()
            .map(|j| (j.blocks.0, j.blocks.1, j.set))
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(dip: f64, spacing: f64) -> JointSet {
        JointSet {
            dip,
            dip_direction: 0.0,
            spacing,
            origin: Coords::default(),
            trace_length: None,
            bridge: 0.0,
            placement: Placement::Regular,
            law: None,
        }
    }

    /// A set names its own field at fault, by the dimension's rules.
    #[test]
    fn sets_check_their_own_values() {
        let field = |set: &JointSet, dimension| match set.check(dimension) {
            Err(DdaError::Setting { field, .. }) => field,
            other => panic!("expected a setting error, got {other:?}"),
        };
        assert!(set(35.0, 1.0).check(2).is_ok());
        assert!(set(-35.0, 1.0).check(2).is_ok());
        assert_eq!(field(&set(-35.0, 1.0), 3), "dip");
        assert_eq!(field(&set(-90.0, 1.0), 2), "dip");
        assert_eq!(field(&set(f64::NAN, 1.0), 2), "dip");
        assert_eq!(field(&set(30.0, 0.0), 2), "spacing");
        let turned = JointSet {
            dip_direction: 45.0,
            ..set(30.0, 1.0)
        };
        assert!(turned.check(3).is_ok());
        assert_eq!(field(&turned, 2), "dip_direction");
        let bridged = JointSet {
            bridge: 0.5,
            ..set(30.0, 1.0)
        };
        assert_eq!(field(&bridged, 2), "bridge");
        assert_eq!(field(&bridged, 3), "bridge");
        let traced = JointSet {
            trace_length: Some(1.5),
            ..bridged
        };
        assert!(traced.check(2).is_ok());
        assert_eq!(field(&traced, 3), "trace_length");
    }

    #[test]
    fn regular_offsets_pass_through_the_origin() {
        let o = offsets(&set(0.0, 1.0), 0.25, -1.0, 2.0, &mut None).unwrap();
        assert_eq!(o, vec![-0.75, 0.25, 1.25]);
        assert!(offsets(&set(0.0, 1e-9), 0.0, 0.0, 1.0, &mut None).is_none());
        assert!(offsets(&set(0.0, 0.0), 0.0, 0.0, 1.0, &mut None).is_none());
    }

    #[test]
    fn random_offsets_have_the_mean_spacing() {
        let mut r = Some(Random(7));
        let o = offsets(&set(0.0, 1.0), 0.0, -2000.0, 2000.0, &mut r).unwrap();
        // 4000 m at a mean spacing of 1 m: about 4000 joints, within 3σ (√4000).
        assert!(
            (o.len() as f64 - 4000.0).abs() < 3.0 * 4000f64.sqrt(),
            "{}",
            o.len()
        );
    }

    #[test]
    fn normals_point_up_the_dip_direction() {
        let n = plane_normal(30.0, 90.0);
        assert!((n - Vector3::new(0.5, 0.0, 3f64.sqrt() / 2.0)).norm() < 1e-15);
        let t = trace_direction(30.0);
        assert!(t.x > 0.0 && t.y < 0.0);
    }
}
