//! Any text through the scene parser, validation and building: errors are
//! fine, panics are not. Seed the corpus with the shipped examples:
//! `cargo +nightly fuzz run scene ../examples`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(scene) = dda::Scene::from_str(text, "fuzz.ron") {
            let _ = scene.build_any();
        }
    }
});
