//! Dry joints hold no tension, so the contact tolerance (the band within
//! which a closed contact may separate before it opens) leaves the answer
//! alone: the shipped jointed slope and Heyman's arch, near their
//! thresholds, move alike at the default tolerance and at one a hundredth
//! as large. Shi's springs, which pull across that band, ended the slope's
//! blocks 3.9 cm and the arch's 0.09 mm away from the finer run.

use dda::Scene;

/// The largest distance between the blocks' centroids at the end of the
/// example run at the default contact tolerance and at `fine`, m.
fn apart(example: &str, fine: f64) -> f64 {
    let path = format!("{}/examples/{example}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    let end = |text: &str| {
        let mut model = Scene::from_str(text, &path).unwrap().build().unwrap();
        model.driver.advance_to(model.duration).unwrap();
        let blocks = &model.driver.system.blocks;
        blocks.iter().map(|b| b.centroid()).collect::<Vec<_>>()
    };
    let coarse = end(&text);
    let text = text.replacen(
        "analysis: (",
        &format!("analysis: (contact_tolerance: {fine:e}, "),
        1,
    );
    let fine = end(&text);
    coarse
        .iter()
        .zip(&fine)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max)
}

#[test]
fn a_jointed_slope_slides_alike_at_a_finer_contact_tolerance() {
    let apart = apart("jointed_slope_2d.ron", 1e-9);
    println!("jointed slope: {apart:.2e} m apart");
    // Its crest wedge slides 0.43 m in the run. Measured: 3.2e-5 m.
    assert!(apart < 1e-3, "{apart} m apart");
}

#[test]
fn an_arch_at_its_threshold_stands_alike_at_a_finer_contact_tolerance() {
    let apart = apart("arch_heyman_2d.ron", 1e-9);
    println!("arch: {apart:.2e} m apart");
    // Measured: 3.6e-5 m.
    assert!(apart < 6e-5, "{apart} m apart");
}
