//! The analytical answers the catalogue compares with (SI units, angles in
//! radians unless a name says degrees).

use nalgebra::Vector3;

/// Distance a block slides from rest down an incline of angle `theta` with
/// friction angle `phi` in time `t` under gravity `g`:
/// ½ g (sin θ − cos θ tan φ) t².
pub fn incline_slide(g: f64, theta: f64, phi: f64, t: f64) -> f64 {
    0.5 * g * (theta.sin() - theta.cos() * phi.tan()) * t * t
}

/// The same with friction `phi1` until the block has slid `d1`, `phi2`
/// after: two parabolas joined at the drop.
pub fn two_stage_slide(g: f64, theta: f64, phi1: f64, phi2: f64, d1: f64, t: f64) -> f64 {
    let a = |phi: f64| g * (theta.sin() - theta.cos() * phi.tan());
    let (a1, a2) = (a(phi1), a(phi2));
    let t1 = (2.0 * d1 / a1).sqrt();
    if t <= t1 {
        0.5 * a1 * t * t
    } else {
        d1 + a1 * t1 * (t - t1) + 0.5 * a2 * (t - t1).powi(2)
    }
}

/// Upward unit normal of a plane of given dip and dip direction (degrees;
/// x east, y north, z up).
pub fn plane_normal(dip: f64, direction: f64) -> Vector3<f64> {
    let (d, a) = (dip.to_radians(), direction.to_radians());
    Vector3::new(d.sin() * a.sin(), d.sin() * a.cos(), d.cos())
}

/// The vector solution for a wedge on two planes with equal friction and
/// gravity along −z: its sliding direction ŝ (along the line of
/// intersection, downward), the share ŵ·ŝ of its weight along ŝ and the
/// planes' normal reactions (N1 + N2)/W, so that
/// a/g = ŵ·ŝ − (N1 + N2)/W · tan φ.
pub fn wedge(n1: Vector3<f64>, n2: Vector3<f64>) -> (Vector3<f64>, f64, f64) {
    let w = Vector3::new(0.0, 0.0, -1.0);
    let m = n1.cross(&n2);
    let s = if m.dot(&w) > 0.0 { m } else { -m }.normalize();
    let m2 = m.norm_squared();
    let r1 = -w.cross(&n2).dot(&m) / m2;
    let r2 = -w.cross(&n1).dot(&n2.cross(&n1)) / m2;
    (s, w.dot(&s), r1 + r2)
}

/// Time for a rigid block of half-width `b` and half-height `h` to rock
/// from the tilt `theta0` at rest down to upright under gravity `g`:
/// θ̈ = −p² sin(α − θ), p² = 3g / (4R), by fine RK4 steps.
pub fn rocking_first_impact(b: f64, h: f64, g: f64, theta0: f64) -> f64 {
    let alpha = (b / h).atan();
    let p2 = 3.0 * g / (4.0 * (b * b + h * h).sqrt());
    let acc = |th: f64| -p2 * (alpha - th).sin();
    let step = 1e-6;
    let (mut th, mut om, mut t) = (theta0, 0.0f64, 0.0);
    while th > 0.0 {
        let k1 = (om, acc(th));
        let k2 = (om + 0.5 * step * k1.1, acc(th + 0.5 * step * k1.0));
        let k3 = (om + 0.5 * step * k2.1, acc(th + 0.5 * step * k2.0));
        let k4 = (om + step * k3.1, acc(th + step * k3.0));
        th += step / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        om += step / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        t += step;
    }
    t
}

/// Newmark's rigid-plastic slip down an incline of angle `theta` with
/// friction angle `phi` by `t_end`, the ground shaken horizontally with
/// acceleration `a_h(t)` (toward +x, the incline descending toward −x):
/// while sliding, or once the ground's push exceeds the yield acceleration,
/// ẍ = g (sin θ − cos θ tan φ) + a_h (cos θ + sin θ tan φ), until the
/// relative velocity is back to zero. Fine explicit steps.
pub fn newmark_slip(g: f64, theta: f64, phi: f64, a_h: impl Fn(f64) -> f64, t_end: f64) -> f64 {
    let mu = phi.tan();
    let h = 1e-6;
    let (mut x, mut v, mut t) = (0.0f64, 0.0f64, 0.0f64);
    while t < t_end {
        let a = g * (theta.sin() - theta.cos() * mu)
            + a_h(t + h / 2.0) * (theta.cos() + theta.sin() * mu);
        if v > 0.0 || a > 0.0 {
            let v1 = (v + a * h).max(0.0);
            x += 0.5 * (v + v1) * h;
            v = v1;
        }
        t += h;
    }
    x
}
