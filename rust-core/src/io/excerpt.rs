//! Quoting a bad cell or field in a message: short and escaped, so a
//! megabyte of garbage or a control character never reaches the terminal
//! whole.

use std::fmt;

/// Characters of a quoted text kept in a message.
pub const EXCERPT_CHARS: usize = 40;

/// A text as quoted in a message: its first [`EXCERPT_CHARS`] characters,
/// escaped as a Rust string literal (`{:?}`), followed by `…` when cut.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Excerpt(String);

impl Excerpt {
    /// The quotation of `text`.
    pub fn of(text: &str) -> Self {
        let mut chars = text.chars();
        let kept: String = chars.by_ref().take(EXCERPT_CHARS).collect();
        let cut = if chars.next().is_some() { "…" } else { "" };
        Excerpt(format!("{kept:?}{cut}"))
    }
}

impl fmt::Display for Excerpt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_texts_are_quoted_whole_and_long_ones_cut() {
        assert_eq!(Excerpt::of("zero").to_string(), "\"zero\"");
        assert_eq!(Excerpt::of("a\u{1b}[2J").to_string(), "\"a\\u{1b}[2J\"");
        let long = "9".repeat(1_000_000);
        let quoted = Excerpt::of(&long).to_string();
        assert_eq!(quoted, format!("\"{}\"…", "9".repeat(EXCERPT_CHARS)));
        let exact = "é".repeat(EXCERPT_CHARS);
        assert_eq!(Excerpt::of(&exact).to_string(), format!("\"{exact}\""));
    }
}
