//! Mutations of real files: bit flips, interesting bytes and numbers, inserted, deleted,
//! duplicated and spliced ranges, truncation; and now and then random bytes alone.

use rand::Rng;
use rand_pcg::Pcg64Mcg;

/// Inputs are kept below this size (a mutation that would pass it is skipped).
pub const MAX_INPUT_BYTES: usize = 4 << 20;

const BYTES: &[u8] = b"\x00\xff\x7f\x80[]{}\"\n-9.,:#e";
/// Numbers that break parsers and arithmetic: limits, overflows, NaN, signs, tiny and huge.
const NUMBERS: &[&str] = &[
    "0",
    "-1",
    "1e308",
    "-1e308",
    "1e999",
    "1e-300",
    "nan",
    "NaN",
    "inf",
    "-inf",
    ".nan",
    "4294967295",
    "4294967296",
    "18446744073709551616",
    "-9223372036854775809",
    "65535",
    "99999999",
    "0.0",
    "-0.0",
    "3.14",
    "1e20",
];

/// A new input from `seeds` (or, one time in ten, random bytes).
pub fn next_input(seeds: &[Vec<u8>], rng: &mut Pcg64Mcg) -> Vec<u8> {
    if seeds.is_empty() || rng.random_range(0..10) == 0 {
        let n = rng.random_range(0..512);
        return (0..n).map(|_| rng.random()).collect();
    }
    let mut data = seeds[rng.random_range(0..seeds.len())].clone();
    for _ in 0..rng.random_range(1..=4) {
        mutate(&mut data, seeds, rng);
    }
    data
}

/// One mutation of `data` in place.
pub fn mutate(data: &mut Vec<u8>, seeds: &[Vec<u8>], rng: &mut Pcg64Mcg) {
    let len = data.len();
    let pos = |rng: &mut Pcg64Mcg| {
        if len == 0 {
            0
        } else {
            rng.random_range(0..len)
        }
    };
    match rng.random_range(0..9) {
        0 if len > 0 => {
            let i = pos(rng);
            data[i] ^= 1 << rng.random_range(0..8);
        }
        1 if len > 0 => {
            let i = pos(rng);
            data[i] = BYTES[rng.random_range(0..BYTES.len())];
        }
        2 => {
            let i = pos(rng);
            let n = rng.random_range(1..=64);
            let byte = BYTES[rng.random_range(0..BYTES.len())];
            let run: Vec<u8> = if rng.random() {
                vec![byte; n]
            } else {
                (0..n).map(|_| rng.random()).collect()
            };
            splice_in(data, i, &run);
        }
        3 if len > 0 => {
            let i = pos(rng);
            let n = rng.random_range(1..=(len - i).min(256));
            data.drain(i..i + n);
        }
        4 if len > 0 => {
            let i = pos(rng);
            let n = rng.random_range(1..=(len - i).min(4096));
            let chunk = data[i..i + n].to_vec();
            let at = pos(rng);
            splice_in(data, at, &chunk);
        }
        5 => replace_number(data, rng),
        6 if len > 0 => data.truncate(pos(rng)),
        7 if !seeds.is_empty() => {
            let other = &seeds[rng.random_range(0..seeds.len())];
            if !other.is_empty() {
                let from = rng.random_range(0..other.len());
                let n = rng.random_range(1..=(other.len() - from).min(4096));
                let at = pos(rng);
                splice_in(data, at, &other[from..from + n]);
            }
        }
        _ => {
            // Repeat a bracket or a line many times: deep nesting, long lists.
            let i = pos(rng);
            let unit: &[u8] =
                [b"[".as_slice(), b"{", b"- ", b"a = 1\n", b"0 "][rng.random_range(0..5)];
            let times = rng.random_range(1..=2000);
            splice_in(data, i, &unit.repeat(times));
        }
    }
}

fn splice_in(data: &mut Vec<u8>, at: usize, bytes: &[u8]) {
    if data.len() + bytes.len() <= MAX_INPUT_BYTES {
        let at = at.min(data.len());
        data.splice(at..at, bytes.iter().copied());
    }
}

/// Replaces a run of digits (a number in a text format) with an interesting number.
fn replace_number(data: &mut Vec<u8>, rng: &mut Pcg64Mcg) {
    let digits: Vec<usize> = data
        .iter()
        .enumerate()
        .filter(|(_, b)| b.is_ascii_digit())
        .map(|(i, _)| i)
        .collect();
    if digits.is_empty() {
        return;
    }
    let mut start = digits[rng.random_range(0..digits.len())];
    while start > 0 && (data[start - 1].is_ascii_digit() || data[start - 1] == b'.') {
        start -= 1;
    }
    let mut end = start;
    while end < data.len() && (data[end].is_ascii_digit() || matches!(data[end], b'.' | b'e')) {
        end += 1;
    }
    let number = NUMBERS[rng.random_range(0..NUMBERS.len())].as_bytes();
    if data.len() - (end - start) + number.len() <= MAX_INPUT_BYTES {
        data.splice(start..end, number.iter().copied());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn mutations_are_seeded_and_stay_within_the_size_cap() {
        let seeds = vec![b"resolution: 0.05\norigin: [1, 2, 0]\n".to_vec()];
        let run = |seed| {
            let mut rng = Pcg64Mcg::seed_from_u64(seed);
            (0..500)
                .map(|_| next_input(&seeds, &mut rng))
                .collect::<Vec<_>>()
        };
        let a = run(1);
        assert_eq!(a, run(1));
        assert_ne!(a, run(2));
        assert!(a.iter().all(|x| x.len() <= MAX_INPUT_BYTES));
        assert!(a.iter().filter(|x| **x != seeds[0]).count() > 400);
    }
}
