//! Scenes mutated at random through the parser, validation and building:
//! none may panic or hang. Each case takes a shipped example and changes a
//! few of its numbers (to zero, negatives, NaN, infinities, huge or tiny
//! values, other numbers of the file), deletes or duplicates a token, or
//! cuts the text short. `DDA_FUZZ_CASES` sets the number of cases (default
//! 5,000; the release check runs 100,000). Reproducers found this way are
//! the regression cases at the end.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};

use dda::Scene;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// The longest one case may take to parse, validate and build. A generator
/// at its 100,000-block limit legitimately takes about 10 s (tested in
/// `bad_input.rs`), so the counts tried here are 10,000 (about 1 s) and
/// beyond the limit (refused at once).
const PATIENCE: Duration = Duration::from_secs(30);

fn examples() -> Vec<(String, String)> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir("examples").unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "ron") {
            let text = std::fs::read_to_string(&path).unwrap();
            out.push((path.display().to_string(), text));
        }
    }
    out.sort();
    out
}

/// Where the numbers of a text are: (start, end) byte ranges.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts = bytes[i].is_ascii_digit()
            && (i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_'));
        if starts {
            let begin = if i > 0 && bytes[i - 1] == b'-' {
                i - 1
            } else {
                i
            };
            let mut j = i;
            while j < bytes.len()
                && (bytes[j].is_ascii_digit()
                    || matches!(bytes[j], b'.' | b'e' | b'E')
                    || (matches!(bytes[j], b'-' | b'+') && matches!(bytes[j - 1], b'e' | b'E')))
            {
                j += 1;
            }
            out.push((begin, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

const ODD: &[&str] = &[
    "0",
    "0.0",
    "-0.0",
    "-1",
    "-1.0",
    "1e308",
    "-1e308",
    "1e-308",
    "5e-324",
    "NaN",
    "inf",
    "-inf",
    "1e30",
    "1e-30",
    "3",
    "100000",
    "1000000",
    "4294967296",
    "18446744073709551616",
    "0.5",
    "2",
    "-1e-9",
    "1e9",
    "7",
];

/// One mutation of one example.
#[derive(Debug, Clone)]
enum Mutation {
    /// The k-th number (modulo their count) becomes `ODD[v]`.
    Number(usize, usize),
    /// The k-th number becomes the j-th number of the file.
    Swap(usize, usize),
    /// The byte range [at, at + len) is removed.
    Delete(usize, usize),
    /// The byte range [at, at + len) is written twice.
    Repeat(usize, usize),
    /// The text ends at `at`.
    Truncate(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        6 => (any::<usize>(), 0..ODD.len()).prop_map(|(k, v)| Mutation::Number(k, v)),
        2 => (any::<usize>(), any::<usize>()).prop_map(|(k, j)| Mutation::Swap(k, j)),
        1 => (any::<usize>(), 1usize..12).prop_map(|(a, l)| Mutation::Delete(a, l)),
        1 => (any::<usize>(), 1usize..40).prop_map(|(a, l)| Mutation::Repeat(a, l)),
        1 => any::<usize>().prop_map(Mutation::Truncate),
    ]
}

/// The largest index at or below `i` that is a character boundary.
fn floor(text: &str, mut i: usize) -> usize {
    i = i.min(text.len());
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

fn apply(text: &str, m: &Mutation) -> String {
    let spans = numbers(text);
    let n = text.len().max(1);
    match *m {
        Mutation::Number(k, v) if !spans.is_empty() => {
            let (a, b) = spans[k % spans.len()];
            format!("{}{}{}", &text[..a], ODD[v], &text[b..])
        }
        Mutation::Swap(k, j) if !spans.is_empty() => {
            let (a, b) = spans[k % spans.len()];
            let (c, d) = spans[j % spans.len()];
            format!("{}{}{}", &text[..a], &text[c..d], &text[b..])
        }
        Mutation::Delete(at, len) => {
            let a = floor(text, at % n);
            let b = floor(text, a + len);
            format!("{}{}", &text[..a], &text[b..])
        }
        Mutation::Repeat(at, len) => {
            let a = floor(text, at % n);
            let b = floor(text, a + len);
            format!("{}{}{}", &text[..b], &text[a..b], &text[b..])
        }
        Mutation::Truncate(at) => text[..floor(text, at % n)].to_string(),
        _ => text.to_string(),
    }
}

/// Parses, validates and builds; an error is fine, a panic or a hang is not.
fn survive(origin: &str, text: &str) -> Result<(), TestCaseError> {
    if let Ok(trace) = std::env::var("DDA_FUZZ_TRACE") {
        // The case about to run, for a case that kills the process.
        std::fs::write(trace, format!("{origin}\n{text}")).unwrap();
    }
    let started = Instant::now();
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        if let Ok(scene) = Scene::from_str(text, origin) {
            let _ = scene.build_any();
        }
    }));
    let took = started.elapsed();
    prop_assert!(outcome.is_ok(), "panicked on:\n{text}");
    prop_assert!(took < PATIENCE, "took {took:?} on:\n{text}");
    Ok(())
}

#[test]
fn mutated_scenes_never_panic_or_hang() {
    let cases: u32 = std::env::var("DDA_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(5_000);
    let examples = examples();
    assert!(examples.len() >= 20, "the examples are the seeds");
    // Panics are caught and reported as failures; keep their messages quiet.
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    // A fixed seed: the suite tries the same scenes on every run, so it
    // never fails by chance; DDA_FUZZ_SEED picks another set.
    let seed: u64 = std::env::var("DDA_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1);
    let mut bytes = [0u8; 32];
    bytes[..8].copy_from_slice(&seed.to_le_bytes());
    let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &bytes);
    let config = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    let mut runner = TestRunner::new_with_rng(config, rng);
    let strategy = (0..examples.len(), prop::collection::vec(mutation(), 1..4));
    let result = runner.run(&strategy, |(which, mutations)| {
        let (origin, text) = &examples[which];
        let text = mutations.iter().fold(text.clone(), |t, m| apply(&t, m));
        survive(origin, &text)
    });
    std::panic::set_hook(hook);
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// Reproducers the fuzzing found, kept as regression cases: an example
/// and the replacement that broke it.
#[test]
fn reproducers_stay_fixed() {
    let cases: &[(&str, &str, &str)] = &[
        // A joint set's origin 1e308 m away: stepping from it joint by joint
        // never advanced (k + 1 rounds to k) and filled the memory.
        (
            "examples/jointed_slope_2d.ron",
            "origin: (1.0, 0.0)",
            "origin: (-1e308, 0.0)",
        ),
        // A 3D region 2,600 m tall cut by joint sets 1.5 and 3 m apart: a
        // million blocks, refused only after minutes of cutting.
        (
            "examples/jointed_slope_3d.ron",
            "(8.0, 3.0, 0.0)",
            "(8.0, 3.0, 2600.0)",
        ),
        // Cross joints 1 mm apart: 34,000 traces, every pair of which was
        // tried for a crossing (90 s of CPU); parallel ones are no longer
        // paired.
        (
            "examples/jointed_slope_2d.ron",
            "(dip: -55.0, spacing: 2.0,",
            "(dip: -55.0, spacing: 0.001,",
        ),
    ];
    for (example, from, to) in cases {
        let text = std::fs::read_to_string(example).unwrap();
        assert!(text.contains(from), "{from} is not in {example}");
        survive(example, &text.replace(from, to)).unwrap();
    }
}
