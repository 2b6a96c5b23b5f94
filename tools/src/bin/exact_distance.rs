//! Exact triangle–triangle distances for a benchmark's worst cases: each
//! line of standard input holds two triangles as 18 numbers (a's three
//! vertices, then b's; decimal text that parses to the f64 values exactly,
//! as Python's `repr` writes them), and each line of output the distance
//! by the exact rational reference: the squared distance exactly, rounded
//! once to f64, then its square root (within an ulp of the true distance).
//!
//! `python python/benchmarks/real_meshes.py` calls it through cargo.

use std::io::{BufRead, Write};

use nearmiss::exact::triangle_distance_f64;
use nearmiss::math::{Point, Triangle};

fn main() {
    let stdin = std::io::stdin();
    let mut out = std::io::BufWriter::new(std::io::stdout());
    for (number, line) in stdin.lock().lines().enumerate() {
        let line = line.unwrap_or_else(|e| fail(number, &e.to_string()));
        if line.trim().is_empty() {
            continue;
        }
        let values: Vec<f64> = line
            .split_whitespace()
            .map(|word| {
                word.parse::<f64>().unwrap_or_else(|_| fail(number, &format!("`{word}` is no number")))
            })
            .collect();
        if values.len() != 18 || values.iter().any(|v| !v.is_finite()) {
            fail(number, "expected 18 finite numbers (two triangles)");
        }
        let triangle = |k: usize| -> Triangle {
            [0, 1, 2].map(|v| Point::new(values[k + 3 * v], values[k + 3 * v + 1], values[k + 3 * v + 2]))
        };
        let _ = writeln!(out, "{:?}", triangle_distance_f64(&triangle(0), &triangle(9)));
    }
}

fn fail(number: usize, message: &str) -> ! {
    eprintln!("error: line {}: {message}", number + 1);
    std::process::exit(2);
}
