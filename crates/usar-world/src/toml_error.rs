//! TOML errors as one line. The `toml` crate's `Display` draws a source snippet over several
//! lines; our errors are one line naming the file, the line and column, and the problem
//! (`r.toml: line 3, column 1: duplicate key `width_m``).

/// One line for a TOML error in `text`: "line L, column C: message", the key or value at
/// the error's place quoted when the message does not name it.
pub fn toml_error_line(text: &str, error: &toml::de::Error) -> String {
    let message = error.message().trim().replace('\n', "; ");
    let Some(span) = error.span().filter(|s| s.start <= text.len()) else {
        return message;
    };
    let before = &text[..floor_char_boundary(text, span.start)];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    let end = floor_char_boundary(text, span.end.min(text.len()));
    let at: String = text[floor_char_boundary(text, span.start)..end]
        .lines()
        .next()
        .unwrap_or("")
        .chars()
        .take(40)
        .collect();
    if at.trim().is_empty() || message.contains(at.trim()) {
        format!("line {line}, column {column}: {message}")
    } else {
        format!("line {line}, column {column}: {message} `{}`", at.trim())
    }
}

fn floor_char_boundary(text: &str, mut i: usize) -> usize {
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line_of(text: &str) -> String {
        let e = toml::from_str::<toml::Table>(text).unwrap_err();
        toml_error_line(text, &e)
    }

    #[test]
    fn a_duplicate_key_is_named_on_one_line() {
        let msg = line_of("a = 1\nwidth_m = 0.5\nwidth_m = 0.6\n");
        assert_eq!(msg, "line 3, column 1: duplicate key `width_m`");
    }

    #[test]
    fn syntax_errors_keep_their_place_and_stay_on_one_line() {
        let msg = line_of("a = [1, 2\nb = \"é\"\n");
        assert!(msg.starts_with("line "), "{msg}");
        assert_eq!(msg.lines().count(), 1, "{msg}");
    }
}
