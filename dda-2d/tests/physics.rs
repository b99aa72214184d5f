//! Physics checks of the 2D system through the core driver, built in code
//! (the scene-file versions of the validation cases live in the root tests).

use dda_2d::{Block, Driver2d, Plane, PlaneElastic, Polygons};
use dda_contact::Coulomb;
use dda_core::{DynContactLaw, Settings};
use nalgebra::{Point2, Rotation2, Vector2};

fn rectangle(cx: f64, cy: f64, w: f64, h: f64, angle: f64) -> Vec<Point2<f64>> {
    let r = Rotation2::new(angle);
    [(-w, -h), (w, -h), (w, h), (-w, h)]
        .iter()
        .map(|&(x, y)| Point2::new(cx, cy) + r * Vector2::new(x / 2.0, y / 2.0))
        .collect()
}

fn elastic(young: f64) -> Box<dyn dda_core::ConstitutiveLaw<3>> {
    Box::new(PlaneElastic { young, poisson: 0.25, plane: Plane::Strain })
}

/// A 1 m block resting on a fixed base inclined at `theta`, friction `phi` (degrees).
fn incline(theta: f64, phi: f64, dt: f64, penalty: f64) -> Driver2d {
    let t = theta.to_radians();
    let (nx, ny) = (-t.sin(), t.cos()); // upward normal of the incline
    let base = rectangle(0.0, 0.0, 20.0, 1.0, t);
    // Block centre 1 m above the base centre along the normal (touching).
    let block = rectangle(nx * 1.0, ny * 1.0, 1.0, 1.0, t);
    let blocks = vec![Block::new(&base, 0, 2700.0).unwrap(), Block::new(&block, 0, 2700.0).unwrap()];
    let mut system = Polygons::new(blocks, vec![elastic(1e10)]);
    system.gravity = Vector2::new(0.0, -9.81);
    system.fix_block(0);
    let laws: Vec<Box<dyn DynContactLaw>> = vec![Box::new(Coulomb::frictional(phi))];
    let settings = Settings { dt: Some(dt), penalty: Some(penalty), ..Settings::default() };
    Driver2d::new(system, laws, settings).unwrap()
}

#[test]
fn free_fall_is_exact() {
    let b = Block::new(&rectangle(0.0, 10.0, 1.0, 1.0, 0.0), 0, 2000.0).unwrap();
    let mut system = Polygons::new(vec![b], vec![elastic(1e9)]);
    system.gravity = Vector2::new(0.0, -9.81);
    let mut d = Driver2d::new(system, vec![Box::new(Coulomb::frictional(30.0))], Settings { dt: Some(0.01), ..Settings::default() }).unwrap();
    d.advance_to(1.0).unwrap();
    let y = d.system.blocks[0].centroid().y;
    let exact = 10.0 - 0.5 * 9.81;
    assert!(((y - exact) / exact).abs() < 1e-12, "y = {y}, exact {exact}");
    let v = d.velocities()[0][1];
    assert!(((v + 9.81) / 9.81).abs() < 1e-12, "v = {v}");
}

#[test]
fn sliding_block_debug() {
  for (p, dt) in [(1e9, 1e-3), (1e10, 1e-3), (1e10, 2e-3), (1e11, 1e-3)] {
    let mut d = incline(30.0, 20.0, dt, p);
    let c0 = d.system.blocks[1].centroid();
    for k in 1..=10 {
        d.advance_to(0.1 * k as f64).unwrap();
        let c = d.system.blocks[1].centroid();
        let t = 0.1 * k as f64;
        let a = 9.81 * (30f64.to_radians().sin() - 30f64.to_radians().cos() * 20f64.to_radians().tan());
        if k == 10 { eprintln!("p={p:e} dt={dt} t={t:.1} dist={:.6} exact={:.6} contacts={} states={:?}", (c - c0).norm(), 0.5 * a * t * t, d.contacts().len(),
            d.contacts().iter().map(|c| c.record.state).collect::<Vec<_>>()); }
    }
  }
}

#[test]
fn sliding_block_first_steps() {
    let mut d = incline(30.0, 20.0, 1e-3, 1e9);
    let t = 30f64.to_radians();
    let a = 9.81 * (t.sin() - t.cos() * 20f64.to_radians().tan());
    let w = d.system.blocks[1].mass * 9.81 * t.cos();
    for k in 1..=30 {
        d.step(1e-3).unwrap();
        let v = d.velocities()[1];
        let along = -(v[0] * t.cos() + v[1] * t.sin());
        let n: f64 = d.contacts().iter().map(|c| c.record.normal_force).sum();
        eprintln!("{k} v={:.6e} exact={:.6e} N/W={:.4} states={:?} oc={}", along, a * 1e-3 * k as f64, n / w,
            d.contacts().iter().map(|c| c.record.state).collect::<Vec<_>>(), d.statistics().open_close_iterations);
    }
}

#[test]
fn resting_block_debug() {
    for (p, dt) in [(1e9, 1e-3), (1e10, 1e-3)] {
        let mut d = incline(30.0, 35.0, dt, p);
        let c0 = d.system.blocks[1].centroid();
        d.advance_to(1.0).unwrap();
        let c1 = d.system.blocks[1].centroid();
        d.advance_to(2.0).unwrap();
        let c2 = d.system.blocks[1].centroid();
        eprintln!("p={p:e} dt={dt}: moved {:.3e} creep {:.3e} {:?}", (c2 - c0).norm(), (c2 - c1).norm(), d.statistics());
    }
}

#[test]
fn stacked_debug() {
    let mut blocks = vec![Block::new(&rectangle(0.0, -0.5, 4.0, 1.0, 0.0), 0, 2700.0).unwrap()];
    for k in 0..10 {
        blocks.push(Block::new(&rectangle(0.0, 0.25 + 0.5 * k as f64, 1.0, 0.5, 0.0), 0, 2700.0).unwrap());
    }
    let mut system = Polygons::new(blocks, vec![elastic(1e12)]);
    system.gravity = Vector2::new(0.0, -9.81);
    system.fix_block(0);
    let p = 1e9;
    let laws: Vec<Box<dyn DynContactLaw>> = vec![Box::new(Coulomb::frictional(30.0))];
    let mut d = Driver2d::new(system, laws, Settings { dt: Some(1e-3), penalty: Some(p), ..Settings::default() }).unwrap();
    let y0 = d.system.blocks[10].centroid().y;
    d.advance_to(1.0).unwrap();
    let c1 = d.system.blocks[10].centroid();
    d.advance_to(5.0).unwrap();
    let c5 = d.system.blocks[10].centroid();
    let w = 2700.0 * 0.5 * 9.81;
    let expected: f64 = (1..=10).map(|k| k as f64 * w / (2.0 * p)).sum();
    eprintln!("settle {:.4e} expected {:.4e} creep {:.3e} contacts {} {:?}", y0 - c5.y, expected, (c5 - c1).norm(), d.contacts().len(), d.statistics());
}

#[test]
fn resting_states_debug() {
    let mut d = incline(30.0, 35.0, 1e-3, 1e9);
    d.advance_to(1.0).unwrap();
    for _ in 0..12 {
        let before = d.statistics().clone();
        d.step(1e-3).unwrap();
        let v = d.velocities()[1];
        eprintln!("v=({:.3e},{:.3e},{:.3e}) {:?} oc={} nr={}", v[0], v[1], v[2],
            d.contacts().iter().map(|c| (c.record.state, c.record.normal_force as i64, c.record.shear_force as i64, c.record.shear[0])).collect::<Vec<_>>(),
            d.statistics().open_close_iterations - before.open_close_iterations, d.statistics().newton_iterations - before.newton_iterations);
    }
}
