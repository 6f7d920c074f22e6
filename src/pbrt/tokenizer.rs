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
        self.text[self.pos..].chars().next()
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
        let tok = |kind, text: String| Ok(Some(Token { kind, text, loc: loc.clone() }));
        match c {
            '[' => tok(TokenKind::Open, "[".into()),
            ']' => tok(TokenKind::Close, "]".into()),
            '"' => {
                let mut s = String::new();
                loop {
                    match self.bump() {
                        None | Some('\n') => {
                            return Err(SceneError::syntax(&loc, &format!("\"{s}"), "unterminated string"))
                        }
                        Some('"') => return tok(TokenKind::Str, s),
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
            c => {
                let mut s = String::from(c);
                while let Some(c) = self.peek() {
                    if c.is_whitespace() || matches!(c, '[' | ']' | '"' | '#') {
                        break;
                    }
                    s.push(c);
                    self.bump();
                }
                tok(TokenKind::Word, s)
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
    fn columns_count_characters_not_bytes() {
        let v = all("\"λμ\" x").unwrap();
        assert_eq!(v[1].3, 6);
    }
}
