//! Tensile strength: a 1 m block hangs from a fixed block by a bonded joint
//! (two corner contacts of L = 0.5 m). It holds while its weight is below
//! T0·L and, above, falls freely once the bond breaks: exact free fall.
//! Holding is a static question (gravity switched on at once would load
//! the joint dynamically, up to twice the weight), so that case runs in
//! static mode.

mod common;

const W: f64 = 2700.0 * 9.81;

fn hang(t0: f64, mode: &str) -> Vec<dda::HistoryRow> {
    let text = format!(
        r#"Scene(
    analysis: (duration: 0.5, dt: 0.001, mode: {mode}, penalty: 1e10, gravity: (0.0, -9.81)),
    output: (interval: 0.05),
    materials: {{ "rock": (density: 2700.0, young: 1e10, poisson: 0.25) }},
    // A cemented joint: cohesion as well, or the slightest shear would
    // exceed a Mohr-Coulomb strength of zero in tension and break the bond.
    default_joint: Coulomb(friction_angle: 30.0, cohesion: {t0}, tensile_strength: {t0}),
    blocks: [
        Rectangle(center: (0.0, 1.5), width: 3.0, height: 1.0, fixed: true),
        Rectangle(center: (0.0, 0.5), width: 1.0, height: 1.0),
    ],
)"#
    );
    let out = common::run_text(&format!("tension_{}", t0 as u64), &text);
    let rows = dda::read_history(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    rows
}

#[test]
fn joint_holds_a_weight_below_its_tensile_strength() {
    let rows = hang(1.25 * W, "Static");
    let drop = common::at(&rows, 1, 0.0).y - common::at(&rows, 1, 0.5).y;
    // Stretched by the weight over two springs (plus a sag of the support).
    assert!(drop > 0.0 && drop < 1e-5, "dropped {drop:e} m");
}

#[test]
fn joint_breaks_above_its_strength_and_the_block_falls_freely() {
    let rows = hang(0.8 * W, "Dynamic");
    let g = 9.81;
    let h = 0.05;
    let block: Vec<&dda::HistoryRow> = rows.iter().filter(|r| r.block == 1).collect();
    assert!(
        block.last().unwrap().y < 0.5 - 0.5 * g * 0.45 * 0.45,
        "the block fell"
    );
    // Constant acceleration −g between outputs after the break, exactly.
    for w in block.windows(3).filter(|w| w[0].time >= 0.1) {
        let second = w[2].y - 2.0 * w[1].y + w[0].y;
        assert!(
            ((second + g * h * h) / (g * h * h)).abs() < 1e-9,
            "t = {}: {second:e}",
            w[1].time
        );
        assert!(w[1].x.abs() < 1e-12 && w[1].vx.abs() < 1e-12);
    }
}
