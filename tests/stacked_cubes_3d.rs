//! A 1 m cube resting on an equal, fixed cube for 5 s, through the scene
//! format: it settles into the contact springs and then must not drift.

use dda::{read_contacts, read_history_3d};
use nalgebra::Vector3;

mod common;

#[test]
fn a_cube_on_a_cube_stays_put_for_five_seconds() {
    let out = common::out_dir("stacked-cubes-3d");
    let text = common::example_with(
        "stacked_cubes_3d.ron",
        "output: (interval: 0.05)",
        "output: (interval: 0.05, contacts: true)",
    );
    std::fs::create_dir_all(&out).unwrap();
    let path = out.join("stacked.ron");
    std::fs::write(&path, text).unwrap();
    dda::run::run(&path, &out).unwrap();
    let rows = read_history_3d(out.join("history.csv")).unwrap();
    let contacts = read_contacts(out.join("contacts.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    let at = |t: f64| {
        let r = rows
            .iter()
            .find(|r| r.block == 1 && (r.time - t).abs() < 1e-9)
            .expect("an output at t");
        Vector3::from(r.position)
    };
    let size = 1.0;
    let drift = (at(5.0) - at(0.0)).norm();
    assert!(drift < 1e-4 * size, "drifted {drift:e} m");
    let creep = (at(5.0) - at(1.0)).norm();
    assert!(creep < 1e-7, "crept {creep:e} m between 1 s and 5 s");
    // At the end the four corners of the upper cube's base carry its weight.
    let last: Vec<_> = contacts
        .iter()
        .filter(|c| (c.time - 5.0).abs() < 1e-9 && c.normal_force > 0.0)
        .collect();
    assert_eq!(last.len(), 4, "{last:?}");
    let total: f64 = last.iter().map(|c| c.normal_force).sum();
    let weight = 2700.0 * 9.81;
    assert!(
        ((total - weight) / weight).abs() < 1e-3,
        "{total} N of {weight} N"
    );
    // Corner on corner, named like `0:v4/1:v0` (vertex 4 of block 0
    // against vertex 0 of block 1).
    for c in &last {
        let pair = (c.block_a.min(c.block_b), c.block_a.max(c.block_b));
        assert_eq!(pair, (0, 1), "{}", c.contact);
        let (a, b) = (format!("{}:v", c.block_a), format!("/{}:", c.block_b));
        assert!(
            c.contact.starts_with(&a) && c.contact.contains(&b),
            "{}",
            c.contact
        );
    }
}
