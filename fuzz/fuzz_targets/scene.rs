//! Any text through the scene parser, validation and building: errors are
//! fine, panics and hangs are not. How to run it: `fuzz/README.md` (seed
//! the corpus with a copy of the examples; libFuzzer writes new inputs into
//! the corpus folder it is given).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(scene) = dda::Scene::from_str(text, "fuzz.ron") {
            let _ = scene.build_any();
        }
    }
});
