//! Exact triangle–triangle distances for a benchmark's worst cases: each
//! line of standard input holds two triangles as 18 numbers (a's three
//! vertices, then b's; decimal text that parses to the f64 values exactly,
//! as Python's `repr` writes them), or as 42: the two triangles in their
//! meshes' frames, then each mesh's pose (its rotation matrix row by row,
//! then its translation), posed exactly. Each line of output is the
//! distance by the exact rational reference: the squared distance
//! exactly, rounded once to f64, then its square root (within an ulp of
//! the true distance).
//!
//! `python python/benchmarks/real_meshes.py` calls it through cargo.

use std::io::{BufRead, Write};

use nalgebra::Matrix3;
use nearmiss::exact::{
    rational_triangle_distance_squared, to_f64, triangle_distance_squared, RationalVector,
};
use nearmiss::math::{Point, Triangle, Vector};

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
        if !matches!(values.len(), 18 | 42) || values.iter().any(|v| !v.is_finite()) {
            fail(number, "expected 18 finite numbers (two triangles) or 42 (two triangles and two poses)");
        }
        let triangle = |k: usize| -> Triangle {
            [0, 1, 2].map(|v| Point::new(values[k + 3 * v], values[k + 3 * v + 1], values[k + 3 * v + 2]))
        };
        let squared = if values.len() == 18 {
            triangle_distance_squared(&triangle(0), &triangle(9))
        } else {
            let posed = |t: Triangle, k: usize| {
                let rotation = Matrix3::from_row_slice(&values[k..k + 9]);
                let translation = Vector::new(values[k + 9], values[k + 10], values[k + 11]);
                t.map(|v| RationalVector::posed(&v, &rotation, &translation))
            };
            rational_triangle_distance_squared(&posed(triangle(0), 18), &posed(triangle(9), 30))
        };
        let _ = writeln!(out, "{:?}", to_f64(&squared).sqrt());
    }
}

fn fail(number: usize, message: &str) -> ! {
    eprintln!("error: line {}: {message}", number + 1);
    std::process::exit(2);
}
