//! Tokenizer for the pbrt-v4 scene format: bare words, quoted strings, `[`, `]`, `#` comments.
//!
//! pbrt-v4 file-format reference ("Overview"): statements are whitespace-separated tokens;
//! strings are double-quoted and may not span lines; `#` starts a comment to the end of the line.

use std::path::Path;
use std::sync::Arc;

use super::error::{Location, SceneError};

/// What kind of token.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TokenKind {
    /// An unquoted word: a directive name, a number or `true`/`false`.
    Word,
    /// A double-quoted string; `text` holds the unescaped contents.
    Str,
    /// `[`
    Open,
    /// `]`
    Close,
}

/// One token with the place it was written.
#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    /// Kind.
    pub kind: TokenKind,
    /// The word, the unescaped string contents, or the bracket.
    pub text: String,
    /// Where the token starts.
    pub loc: Location,
}

impl Token {
    /// The token as it appeared in the file (strings re-quoted), for error messages.
    pub fn display(&self) -> String {
        match self.kind {
            TokenKind::Str => format!("\"{}\"", self.text),
            _ => self.text.clone(),
        }
    }
}

/// Splits scene text into tokens lazily.
pub struct Tokenizer {
    text: String,
    /// Byte offset of the next character.
    pos: usize,
    file: Arc<Path>,
    search_dir: Option<Arc<Path>>,
    line: u32,
    col: u32,
}

impl Tokenizer {
    /// A tokenizer over `text`, reporting locations in `file`.
    pub fn new(text: impl Into<String>, file: Arc<Path>) -> Self {
        Self { text: text.into(), pos: 0, file, search_dir: None, line: 1, col: 1 }
    }

    fn peek(&self) -> Option<char> {
        match self.text.as_bytes().get(self.pos) {
            Some(&b) if b.is_ascii() => Some(b as char),
            Some(_) => self.text[self.pos..].chars().next(),
            None => None,
        }
    }

    /// Relative file names in the text resolve against `dir` ([`Location::resolve`]).
    pub fn with_search_dir(mut self, dir: Option<Arc<Path>>) -> Self {
        self.search_dir = dir;
        self
    }

    fn bump(&mut self) -> Option<char> {
        let c = self.peek()?;
        self.pos += c.len_utf8();
        if c == '\n' {
            self.line += 1;
            self.col = 1;
        } else {
            self.col += 1;
        }
        Some(c)
    }

    fn here(&self) -> Location {
        Location { search_dir: self.search_dir.clone(), ..Location::new(self.file.clone(), self.line, self.col) }
    }

    /// The next token, `Ok(None)` at the end of the text.
    pub fn next_token(&mut self) -> Result<Option<Token>, SceneError> {
        loop {
            // ASCII blanks byte by byte; anything else goes the general way below.
            match self.text.as_bytes().get(self.pos) {
                Some(b'\n') => {
                    (self.pos, self.line, self.col) = (self.pos + 1, self.line + 1, 1);
                    continue;
                }
                Some(b' ' | b'\t' | b'\r') => {
                    (self.pos, self.col) = (self.pos + 1, self.col + 1);
                    continue;
                }
                _ => {}
            }
            match self.peek() {
                None => return Ok(None),
                Some(c) if c.is_whitespace() => {
                    self.bump();
                }
                Some('#') => {
                    while let Some(c) = self.peek() {
                        if c == '\n' {
                            break;
                        }
                        self.bump();
                    }
                }
                Some(_) => break,
            }
        }
        let loc = self.here();
        let c = self.bump().expect("peeked a character");
        let tok = |kind, text: String, loc: Location| Ok(Some(Token { kind, text, loc }));
        match c {
            '[' => tok(TokenKind::Open, "[".into(), loc),
            ']' => tok(TokenKind::Close, "]".into(), loc),
            '"' => {
                // Most strings hold no escape: take them whole.
                let rest = &self.text[self.pos..];
                if let Some(end) = rest.find(['"', '\\', '\n']).filter(|&e| rest.as_bytes()[e] == b'"') {
                    let s = rest[..end].to_string();
                    self.col += s.chars().count() as u32 + 1;
                    self.pos += end + 1;
                    return tok(TokenKind::Str, s, loc);
                }
                let mut s = String::new();
                loop {
                    match self.bump() {
                        None | Some('\n') => {
                            return Err(SceneError::syntax(&loc, &format!("\"{s}"), "unterminated string"))
                        }
                        Some('"') => return tok(TokenKind::Str, s, loc),
                        Some('\\') => {
                            let e = match self.bump() {
                                Some('n') => '\n',
                                Some('t') => '\t',
                                Some('r') => '\r',
                                Some('b') => '\u{8}',
                                Some('f') => '\u{c}',
                                Some('\\') => '\\',
                                Some('\'') => '\'',
                                Some('"') => '"',
                                other => {
                                    let shown = other.map(String::from).unwrap_or_default();
                                    return Err(SceneError::syntax(
                                        &loc,
                                        &format!("\\{shown}"),
                                        "unknown escape sequence in string",
                                    ));
                                }
                            };
                            s.push(e);
                        }
                        Some(c) => s.push(c),
                    }
                }
            }
            _ => {
                // A word has no line break, so only the column moves: one per character.
                let start = self.pos - c.len_utf8();
                let rest = &self.text.as_bytes()[self.pos..];
                let ascii = rest.iter().position(|&b| {
                    !b.is_ascii() || b.is_ascii_whitespace() || matches!(b, 0x0b | b'[' | b']' | b'"' | b'#')
                });
                let mut len = ascii.unwrap_or(rest.len());
                if rest.get(len).is_some_and(|b| !b.is_ascii()) {
                    let rest = &self.text[self.pos..];
                    len = rest
                        .find(|c: char| c.is_whitespace() || matches!(c, '[' | ']' | '"' | '#'))
                        .unwrap_or(rest.len());
                }
                self.col += self.text[self.pos..self.pos + len].chars().count() as u32;
                self.pos += len;
                tok(TokenKind::Word, self.text[start..self.pos].to_string(), loc)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(text: &str) -> Result<Vec<(TokenKind, String, u32, u32)>, SceneError> {
        let mut t = Tokenizer::new(text, Arc::from(Path::new("t.pbrt")));
        let mut v = Vec::new();
        while let Some(tok) = t.next_token()? {
            v.push((tok.kind, tok.text, tok.loc.line, tok.loc.col));
        }
        Ok(v)
    }

    #[test]
    fn words_strings_brackets_comments_and_positions() {
        use TokenKind::*;
        let v = all("Shape \"sphere\" # comment [ ignored\n  \"float radius\" [2.5]").unwrap();
        assert_eq!(
            v,
            vec![
                (Word, "Shape".into(), 1, 1),
                (Str, "sphere".into(), 1, 7),
                (Str, "float radius".into(), 2, 3),
                (Open, "[".into(), 2, 18),
                (Word, "2.5".into(), 2, 19),
                (Close, "]".into(), 2, 22),
            ]
        );
    }

    #[test]
    fn escapes_are_unescaped() {
        let v = all(r#""a\"b\\c\nd""#).unwrap();
        assert_eq!(v[0].1, "a\"b\\c\nd");
    }

    #[test]
    fn unterminated_string_is_an_error_with_location() {
        let e = all("Shape\n  \"sphere").unwrap_err();
        assert_eq!(e.to_string(), "t.pbrt:2:3: unterminated string (at \"\"sphere\")");
        let e = all("\"a\nb\"").unwrap_err();
        assert_eq!(e.location().line, 1);
    }

    #[test]
    fn bad_escape_is_an_error() {
        let e = all(r#""a\q""#).unwrap_err();
        assert_eq!(e.to_string(), "t.pbrt:1:1: unknown escape sequence in string (at \"\\q\")");
    }

    #[test]
    fn unusual_blanks_and_non_ascii_words_keep_their_places() {
        use TokenKind::*;
        let v = all("a\u{b}b\u{c}\tc\r\n  wörd\u{a0}x \"s\u{2003}t\"\u{2003}]").unwrap();
        let want = [
            (Word, "a", 1, 1),
            (Word, "b", 1, 3),
            (Word, "c", 1, 6),
            (Word, "wörd", 2, 3),
            (Word, "x", 2, 8),
            (Str, "s\u{2003}t", 2, 10),
            (Close, "]", 2, 16),
        ];
        let got: Vec<_> = v.iter().map(|(k, t, l, c)| (*k, t.as_str(), *l, *c)).collect();
        assert_eq!(got, want);
    }

    #[test]
    fn columns_count_characters_not_bytes() {
        let v = all("\"λμ\" x").unwrap();
        assert_eq!(v[1].3, 6);
    }
}
