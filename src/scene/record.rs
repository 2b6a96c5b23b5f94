//! Rewriting a scene file's `expect` field in place (`nearmiss test
//! --record`), keeping everything else of the text, comments included.
//!
//! A span-aware edit: a small scanner walks the RON text token by token
//! (strings, raw strings and characters read whole, comments skipped,
//! bracket depth tracked) and notes where each top-level field's value
//! begins and where its last token ends. The scene's `expect:` value is
//! replaced by exactly that span, or a new field is added after the last
//! field's last token (a comma there if there is none, never inside a
//! comment that follows it).

/// The comment put above a recorded expectation.
pub const RECORDED_COMMENT: &str =
    "// expect: recorded by `nearmiss test --record` from a run, not derived by analysis";

/// Where the scanner found the scene's parts.
struct Spans {
    /// The `expect` value: from after its colon to the end of its last token.
    expect: Option<(usize, usize)>,
    /// The scene's closing parenthesis.
    close: usize,
    /// The end of the last token before the closing parenthesis.
    last_token_end: usize,
}

/// The end of the string, raw string or character literal starting at
/// `i`, or `None` if none starts there.
fn literal_end(text: &str, i: usize) -> Option<usize> {
    let bytes = text.as_bytes();
    match bytes[i] {
        b'"' => {
            let mut k = i + 1;
            while k < bytes.len() && bytes[k] != b'"' {
                k += if bytes[k] == b'\\' { 2 } else { 1 };
            }
            Some((k + 1).min(bytes.len()))
        }
        b'\'' => {
            let mut k = i + 1;
            while k < bytes.len() && bytes[k] != b'\'' {
                k += if bytes[k] == b'\\' { 2 } else { 1 };
            }
            Some((k + 1).min(bytes.len()))
        }
        // r"...", r#"..."#: the quote closes with as many hashes.
        b'r' if !i.checked_sub(1).is_some_and(|k| bytes[k].is_ascii_alphanumeric() || bytes[k] == b'_') => {
            let hashes = bytes[i + 1..].iter().take_while(|&&b| b == b'#').count();
            if bytes.get(i + 1 + hashes) != Some(&b'"') {
                return None;
            }
            let closing = format!("\"{}", "#".repeat(hashes));
            let body = i + 2 + hashes;
            Some(text[body..].find(&closing).map_or(bytes.len(), |k| body + k + closing.len()))
        }
        _ => None,
    }
}

fn scan(text: &str) -> Result<Spans, String> {
    let bytes = text.as_bytes();
    let mut depth = 0usize;
    let mut i = 0;
    let mut last_token_end = 0;
    let mut expect = None;
    // The start of the `expect` value, while it is being scanned.
    let mut value_start = None::<usize>;
    while i < bytes.len() {
        let byte = bytes[i];
        if byte.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        if byte == b'/' && bytes.get(i + 1) == Some(&b'/') {
            i = text[i..].find('\n').map_or(bytes.len(), |k| i + k);
            continue;
        }
        if byte == b'/' && bytes.get(i + 1) == Some(&b'*') {
            i = text[i + 2..].find("*/").map_or(bytes.len(), |k| i + 2 + k + 2);
            continue;
        }
        if let Some(end) = literal_end(text, i) {
            i = end;
            last_token_end = end;
            continue;
        }
        match byte {
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => {
                if depth == 1 {
                    if let Some(start) = value_start.take() {
                        expect = Some((start, last_token_end));
                    }
                    return Ok(Spans { expect, close: i, last_token_end });
                }
                depth = depth.saturating_sub(1);
            }
            b',' if depth == 1 => {
                if let Some(start) = value_start.take() {
                    expect = Some((start, last_token_end));
                }
            }
            b'e' if depth == 1
                && value_start.is_none()
                && expect.is_none()
                && text[i..].starts_with("expect")
                && !i
                    .checked_sub(1)
                    .is_some_and(|k| bytes[k].is_ascii_alphanumeric() || bytes[k] == b'_') =>
            {
                let after = text[i + "expect".len()..].trim_start();
                if after.starts_with(':') {
                    let colon = text.len() - after.len();
                    value_start = Some(colon + 1);
                    i = colon + 1;
                    last_token_end = i;
                    continue;
                }
            }
            _ => {}
        }
        // Identifiers and numbers advance a byte at a time; their end is
        // the last byte seen.
        i += 1;
        last_token_end = i;
    }
    Err("no closing parenthesis of `Scene(...)` found".into())
}

/// `text` with its top-level `expect` field set to `value` (RON), marked
/// by [`RECORDED_COMMENT`]; an error if the text's structure is not a
/// `Scene(...)` the scanner can follow.
pub fn set_expectation(text: &str, value: &str) -> Result<String, String> {
    let spans = scan(text)?;
    match spans.expect {
        Some((start, end)) => {
            // Mark it, unless the line above already carries the mark.
            let field = text[..start].rfind("expect").unwrap_or(start);
            let line_start = text[..field].rfind('\n').map_or(0, |k| k + 1);
            let indent = &text[line_start..field];
            let marked = text[..line_start].trim_end().ends_with(RECORDED_COMMENT);
            let mark = if marked || !indent.trim().is_empty() {
                String::new()
            } else {
                format!("{indent}{RECORDED_COMMENT}\n")
            };
            Ok(format!("{}{mark}{} {value}{}", &text[..line_start], &text[line_start..start], &text[end..]))
        }
        None => {
            let last = spans.last_token_end;
            let comma = if matches!(text[..last].bytes().last(), Some(b',' | b'(')) { "" } else { "," };
            // Whatever follows the last token (a comment) stays where it is.
            let between = text[last..spans.close].trim_end();
            Ok(format!(
                "{}{comma}{between}\n    {RECORDED_COMMENT}\n    expect: {value},\n{}",
                &text[..last],
                &text[spans.close..]
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_expect_field_is_replaced_and_comments_and_strings_are_left_alone() {
        let text = "// expect: in a comment\nScene(\n    name: \"expect: x\",\n    dt: 0.1,\n    expect: NoContact,\n    steps: 1,\n)";
        let out = set_expectation(
            text,
            "Contact(time: 1.0, tolerance: 0.1, bodies: (\"a\", \"b\"), recorded: true)",
        )
        .unwrap();
        assert!(out.starts_with("// expect: in a comment\nScene(\n    name: \"expect: x\",\n    dt: 0.1,\n"));
        assert!(out.contains(&format!("    {RECORDED_COMMENT}\n    expect: Contact(time: 1.0")));
        assert!(out.ends_with("recorded: true),\n    steps: 1,\n)"));
        // Recording again replaces the value and keeps one mark.
        let again = set_expectation(&out, "NoContact").unwrap();
        assert_eq!(again.matches(RECORDED_COMMENT).count(), 1);
        assert!(again.contains("    expect: NoContact,\n    steps: 1"));
    }

    #[test]
    fn look_alike_names_and_an_unnamed_struct_are_handled() {
        // `expected_speed` is not `expect`; the struct name may be omitted.
        let text = "(expected_speed: 1.0, name: \"s\", expect: NoContact)";
        let out = set_expectation(text, "NoContact").unwrap();
        assert!(out.starts_with("(expected_speed: 1.0, name: \"s\", expect: NoContact)"), "{out}");
        let text = "(expected_speed: 1.0)";
        assert!(set_expectation(text, "NoContact").unwrap().contains("expected_speed: 1.0,\n"));
    }

    #[test]
    fn a_missing_expect_field_is_added_before_the_closing_parenthesis() {
        let out =
            set_expectation("Scene(name: \"s\", dt: 0.1, steps: 1, bodies: [(name: \"a\")])", "NoContact")
                .unwrap();
        assert!(out.ends_with(&format!(
            "bodies: [(name: \"a\")],\n    {RECORDED_COMMENT}\n    expect: NoContact,\n)"
        )));
        assert!(set_expectation("Scene(name: \"s\"", "NoContact").is_err());
    }

    /// The symptoms of issue 29: a trailing comment after the last field
    /// got the comma (`< 3e-9.,`), and a last field without a comma before
    /// a comment made a file that did not load.
    #[test]
    fn comments_after_the_last_field_keep_their_text_and_the_comma_goes_after_the_value() {
        let text = "Scene(\n    name: \"s\",\n    dt: 0.1 // the gap is < 3e-9.\n)\n";
        let out = set_expectation(text, "NoContact").unwrap();
        assert_eq!(
            out,
            format!("Scene(\n    name: \"s\",\n    dt: 0.1, // the gap is < 3e-9.\n    {RECORDED_COMMENT}\n    expect: NoContact,\n)\n")
        );
        // The same with a block comment, and with a comma already there.
        let text = "Scene(name: \"s\", dt: 0.1 /* note, (not a field) */)";
        let out = set_expectation(text, "NoContact").unwrap();
        assert!(out.starts_with("Scene(name: \"s\", dt: 0.1, /* note, (not a field) */\n"), "{out}");
        let text = "Scene(name: \"s\", dt: 0.1, // last\n)";
        let out = set_expectation(text, "NoContact").unwrap();
        assert!(out.starts_with("Scene(name: \"s\", dt: 0.1, // last\n    //"), "{out}");
        // An `expect` value followed by a comment and no comma: only the
        // value is replaced.
        let text = "Scene(name: \"s\", expect: NoContact // was derived\n)";
        let out = set_expectation(text, "Contact(time: 1.0)").unwrap();
        assert!(out.ends_with("expect: Contact(time: 1.0) // was derived\n)"), "{out}");
    }

    #[test]
    fn strings_raw_strings_and_characters_are_read_whole() {
        let text = "Scene(name: r#\"a \"expect: x\" )\"#, tag: ')', path: \"b\\\"c)\")";
        let out = set_expectation(text, "NoContact").unwrap();
        assert!(
            out.starts_with("Scene(name: r#\"a \"expect: x\" )\"#, tag: ')', path: \"b\\\"c)\",\n"),
            "{out}"
        );
    }
}
