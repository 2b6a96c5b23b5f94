//! STL through `stl_io`: binary (told by its size, whatever its header
//! says) and ASCII (`solid` with or without a name). Each facet's corners
//! come apart; [`super::files::weld`] joins them.

use std::borrow::Cow;
use std::io::Cursor;

use super::files::{checked_point, Malformed, MeshFormat, Soup};

/// Reads an STL file's `bytes` as `format` (binary or ASCII).
pub(super) fn read(mut bytes: Vec<u8>, format: MeshFormat) -> Result<Soup, Malformed> {
    let ascii = format == MeshFormat::AsciiStl;
    if !ascii {
        check_binary_size(&bytes)?;
        // `stl_io` takes a file whose first line begins `solid ` for ASCII;
        // this one is binary by its size, so its free-text header (which
        // nothing reads) is kept from saying so.
        bytes[0] = b' ';
    }
    let data = if ascii { ascii_with_named_solid(&bytes) } else { Cow::Borrowed(bytes.as_slice()) };
    let place = |k: usize| facet_place(k, ascii.then_some(bytes.as_slice()));
    let mut cursor = Cursor::new(data.as_ref());
    let reader =
        stl_io::create_stl_reader(&mut cursor).map_err(|e| Malformed::at("line 1", e.to_string()))?;
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for (k, facet) in reader.enumerate() {
        let facet = facet.map_err(|e| match ascii.then(|| bad_number(&bytes, k)).flatten() {
            Some((line, word)) => {
                Malformed::at(format!("facet {} (line {line})", k + 1), format!("`{word}` is not a number"))
            }
            None => Malformed::at(place(k), e.to_string()),
        })?;
        let first = vertices.len() as u32;
        for corner in facet.vertices {
            vertices.push(checked_point(corner.0.map(f64::from), || place(k))?);
        }
        triangles.push([first, first + 1, first + 2]);
    }
    Ok(Soup { vertices, triangles, dropped: 0 })
}

/// The triangle count a binary STL states at byte 80.
pub(super) fn stated_count(bytes: &[u8]) -> Option<u32> {
    Some(u32::from_le_bytes(bytes.get(80..84)?.try_into().ok()?))
}

/// The size of a binary STL of `count` triangles: 84 bytes (header and
/// count) and 50 a facet.
pub(super) fn binary_size(count: u32) -> u64 {
    84 + 50 * u64::from(count)
}

/// A binary STL's size must be [`binary_size`] of the count it states.
fn check_binary_size(bytes: &[u8]) -> Result<(), Malformed> {
    let Some(count) = stated_count(bytes) else {
        return Err(Malformed::at(
            "the header",
            format!(
                "the file has {} bytes, fewer than the 84 of a binary STL's header and triangle count",
                bytes.len()
            ),
        ));
    };
    let expected = binary_size(count);
    if bytes.len() as u64 != expected {
        return Err(Malformed::at(
            "the header",
            format!(
                "it states {count} triangles, so 84 + 50 × {count} = {expected} bytes, but the file has {} (cut short, or not an STL)",
                bytes.len()
            ),
        ));
    }
    Ok(())
}

/// ASCII STL text as `stl_io` reads it: no byte-order mark, and `solid `
/// with its space even where the solid has no name, first (errors are
/// placed in the file as it is, by [`facet_place`]).
fn ascii_with_named_solid(bytes: &[u8]) -> Cow<'_, [u8]> {
    let text = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(bytes);
    let start = text.len() - text.trim_ascii_start().len();
    let (blank, rest) = text.split_at(start);
    let rest = rest.strip_prefix(b"solid").unwrap_or(rest);
    if blank.is_empty() && rest.starts_with(b" ") && text.len() == bytes.len() {
        return Cow::Borrowed(bytes);
    }
    let mut named = b"solid ".to_vec();
    named.extend_from_slice(rest);
    Cow::Owned(named)
}

/// Where facet `k` (0-based) is: its number, and in ASCII `text` the line
/// of its `facet` word (or the end, for a facet that never began).
fn facet_place(k: usize, text: Option<&[u8]>) -> String {
    let Some(text) = text else { return format!("facet {}", k + 1) };
    let mut facets = 0;
    let mut lines = 0;
    for (number, line) in text.split(|&b| b == b'\n').enumerate() {
        lines = number + 1;
        if line.trim_ascii_start().starts_with(b"facet") {
            if facets == k {
                return format!("facet {} (line {})", k + 1, number + 1);
            }
            facets += 1;
        }
    }
    format!("after facet {k} (line {lines})")
}

/// The first word of ASCII facet `k` (0-based) that should be a number and
/// is not (in its `facet normal` or `vertex` lines), with its line.
fn bad_number(text: &[u8], k: usize) -> Option<(usize, String)> {
    let mut facets = 0;
    for (number, line) in String::from_utf8_lossy(text).lines().enumerate() {
        let mut words = line.split_ascii_whitespace();
        // The words before the numbers: `facet normal`, `vertex`.
        let keywords = match words.next() {
            Some("facet") => {
                facets += 1;
                1
            }
            Some("vertex") if facets == k + 1 => 0,
            Some("endfacet") if facets == k + 1 => return None,
            _ => continue,
        };
        if facets == k + 1 {
            if let Some(word) = words.skip(keywords).find(|w| !w.parse::<f32>().is_ok_and(f32::is_finite)) {
                return Some((number + 1, word.chars().take(40).collect()));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn facets_are_placed_by_their_line() {
        let text = b"solid a\nfacet normal 0 0 1\nouter loop\nendloop\nendfacet\n  facet normal 0 0 1\n";
        assert_eq!(facet_place(1, Some(text)), "facet 2 (line 6)");
        assert_eq!(facet_place(2, Some(text)), "after facet 2 (line 7)");
        assert_eq!(facet_place(4, None), "facet 5");
    }
}
