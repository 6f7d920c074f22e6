//! Tokenizer for the pbrt-v4 scene format: bare words, quoted strings, `[`, `]`, `#` comments.
//!
//! pbrt-v4 file-format reference ("Overview"): statements are whitespace-separated tokens;
//! strings are double-quoted and may not span lines; `#` starts a comment to the end of the line.

use std::borrow::Cow;
use std::cell::OnceCell;
use std::path::Path;
use std::sync::Arc;

use super::error::{Location, SceneError};
use super::location::SourceName;

/// The text of one scene file and its [`SourceName`], which locations in it share.
///
/// Tokens carry a byte offset only; a location is that offset and the shared name, whose line
/// and column are found when a message is written.
pub struct SourceFile {
    name: Arc<SourceName>,
    text: String,
}

impl SourceFile {
    /// The text `text` of `path`, whose relative file names resolve against `search_dir`
    /// ([`Location::resolve`]). A leading UTF-8 byte-order mark (prepended by some editors) is
    /// dropped.
    pub fn new(path: Arc<Path>, search_dir: Option<Arc<Path>>, mut text: String) -> Self {
        if text.starts_with('\u{feff}') {
            text.drain(..'\u{feff}'.len_utf8());
        }
        Self { name: Arc::new(SourceName::new(path, search_dir, &text)), text }
    }

    /// The text.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The file's path as written.
    pub fn path(&self) -> &Path {
        self.name.path()
    }

    /// The location of byte `offset` (a character boundary).
    pub fn location(&self, offset: usize) -> Location {
        Location::at_offset(&self.name, offset)
    }
}

/// Scene files kept while a parse reads them, so that tokens can borrow their text: a file
/// added stays until the collection is dropped.
#[derive(Default)]
pub struct SourceFiles {
    head: OnceCell<Box<FileNode>>,
}

struct FileNode {
    file: SourceFile,
    next: OnceCell<Box<FileNode>>,
}

impl SourceFiles {
    /// Keeps `file` and lends it for as long as the collection lives.
    pub fn add(&self, file: SourceFile) -> &SourceFile {
        let mut cell = &self.head;
        while let Some(node) = cell.get() {
            cell = &node.next;
        }
        &cell.get_or_init(|| Box::new(FileNode { file, next: OnceCell::new() })).file
    }
}

impl Drop for SourceFiles {
    /// One file after the other (a recursive drop of a long chain could exhaust the stack).
    fn drop(&mut self) {
        let mut next = self.head.take();
        while let Some(mut node) = next {
            next = node.next.take();
        }
    }
}

/// What kind of token.
///
/// As wide as a pointer, so that a [`Token`] has no padding: moving one (tokens are returned,
/// peeked and collected by value) then copies whole words, where a one-byte kind left seven
/// bytes of padding that were copied in overlapping pieces, which stalls store-to-load
/// forwarding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(usize)]
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

/// One token: its text, borrowed from the file unless a string held escapes, and where it
/// starts.
#[derive(Clone)]
pub struct Token<'a> {
    /// Kind.
    pub kind: TokenKind,
    /// The word, the unescaped string contents, or the bracket.
    pub text: Cow<'a, str>,
    /// Byte offset of its first character in `file`.
    pub offset: usize,
    /// The file it was read from.
    pub file: &'a SourceFile,
}

impl std::fmt::Debug for Token<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?} {:?} at {}", self.kind, self.text, self.loc())
    }
}

impl Token<'_> {
    /// Where the token starts.
    pub fn loc(&self) -> Location {
        self.file.location(self.offset)
    }

    /// The token as it appeared in the file (strings re-quoted), for error messages.
    pub fn display(&self) -> String {
        match self.kind {
            TokenKind::Str => format!("\"{}\"", self.text),
            _ => self.text.to_string(),
        }
    }
}

/// Whether an ASCII byte ends a word: a blank (vertical tab included), a bracket, a quote or a
/// comment sign.
/// An ASCII blank of the scene format (vertical tab included).
pub(super) fn is_blank(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n' | 0x0b | 0x0c)
}

const fn ends_word(b: u8) -> bool {
    b.is_ascii_whitespace() || matches!(b, 0x0b | b'[' | b']' | b'"' | b'#')
}

/// For each byte, whether a word's ASCII fast path stops at it: [`ends_word`], or a byte of a
/// non-ASCII character (looked at as a character).
static STOPS_WORD: [bool; 256] = {
    let mut t = [false; 256];
    let mut b = 0;
    while b < 256 {
        t[b] = b >= 0x80 || ends_word(b as u8);
        b += 1;
    }
    t
};

/// The text between a `[` and the `]` that closes it, when it is all ASCII words and blanks:
/// a list of numbers to be read without tokens ([`super::number_list`]).
pub struct NumberSpan<'a> {
    /// The file it is in.
    pub file: &'a SourceFile,
    /// Byte offset of its first character in `file`.
    pub offset: usize,
    /// The text, brackets excluded.
    pub text: &'a str,
}

/// Splits scene text into tokens lazily.
pub struct Tokenizer<'a> {
    file: &'a SourceFile,
    /// Byte offset of the next character.
    pos: usize,
}

impl<'a> Tokenizer<'a> {
    /// A tokenizer over the text of `file`.
    pub fn new(file: &'a SourceFile) -> Self {
        Self { file, pos: 0 }
    }

    /// The next token, `Ok(None)` at the end of the text.
    pub fn next_token(&mut self) -> Result<Option<Token<'a>>, SceneError> {
        let text: &'a str = &self.file.text;
        let bytes = text.as_bytes();
        // Blanks and comments: ASCII byte by byte, anything else as a character.
        loop {
            match bytes.get(self.pos) {
                None => return Ok(None),
                Some(&b) if is_blank(b) => self.pos += 1,
                Some(b'#') => {
                    self.pos = memchr::memchr(b'\n', &bytes[self.pos..]).map_or(bytes.len(), |i| self.pos + i);
                }
                Some(b) if b.is_ascii() => break,
                Some(_) => match text[self.pos..].chars().next() {
                    Some(c) if c.is_whitespace() => self.pos += c.len_utf8(),
                    _ => break,
                },
            }
        }
        let start = self.pos;
        let token = |kind, text: Cow<'a, str>| Ok(Some(Token { kind, text, offset: start, file: self.file }));
        match bytes[start] {
            b'[' => {
                self.pos += 1;
                token(TokenKind::Open, Cow::Borrowed(&text[start..start + 1]))
            }
            b']' => {
                self.pos += 1;
                token(TokenKind::Close, Cow::Borrowed(&text[start..start + 1]))
            }
            b'"' => {
                let body = start + 1;
                let end = memchr::memchr3(b'"', b'\\', b'\n', &bytes[body..]).map(|i| body + i);
                if let Some(end) = end.filter(|&e| bytes[e] == b'"') {
                    // Most strings hold no escape: borrow them whole.
                    self.pos = end + 1;
                    return token(TokenKind::Str, Cow::Borrowed(&text[body..end]));
                }
                self.escaped_string(start)
                    .map(|s| Some(Token { kind: TokenKind::Str, text: Cow::Owned(s), offset: start, file: self.file }))
            }
            _ => {
                // A word has no line break and runs to a blank, a bracket, a quote or a '#'.
                let rest = &bytes[start..];
                let mut len = rest.iter().position(|&b| STOPS_WORD[usize::from(b)]).unwrap_or(rest.len());
                if rest.get(len).is_some_and(|b| !b.is_ascii()) {
                    let rest = &text[start..];
                    len = rest
                        .find(|c: char| c.is_whitespace() || matches!(c, '[' | ']' | '"' | '#'))
                        .unwrap_or(rest.len());
                }
                self.pos = start + len;
                token(TokenKind::Word, Cow::Borrowed(&text[start..self.pos]))
            }
        }
    }

    /// Right after a `[`: the text up to the next `]` of this file, which then comes next, if
    /// that text holds no string, comment, bracket or non-ASCII character; `None`, with the
    /// position unchanged, otherwise (also when the file has no `]` left: a list may go on in
    /// the file that included this one).
    pub fn number_span(&mut self) -> Option<NumberSpan<'a>> {
        let text: &'a str = &self.file.text;
        let start = self.pos;
        let close = start + memchr::memchr(b']', &text.as_bytes()[start..])?;
        let span = &text[start..close];
        if !span.is_ascii() || memchr::memchr3(b'"', b'[', b'#', span.as_bytes()).is_some() {
            return None;
        }
        self.pos = close + 1;
        Some(NumberSpan { file: self.file, offset: start, text: span })
    }

    /// The text from here to the end of the `n`-th word ahead, which then comes next, when the
    /// `n` words come before any string, bracket, comment or non-ASCII character; `None`, with
    /// the position unchanged, otherwise.
    pub fn word_span(&mut self, n: usize) -> Option<NumberSpan<'a>> {
        let text: &'a str = &self.file.text;
        let bytes = text.as_bytes();
        let (start, mut i) = (self.pos, self.pos);
        for _ in 0..n {
            while bytes.get(i).is_some_and(|&b| is_blank(b)) {
                i += 1;
            }
            let word = i;
            while bytes.get(i).is_some_and(|&b| !STOPS_WORD[usize::from(b)]) {
                i += 1;
            }
            if i == word {
                return None;
            }
        }
        if bytes.get(i).is_some_and(|b| !b.is_ascii()) {
            return None;
        }
        self.pos = i;
        Some(NumberSpan { file: self.file, offset: start, text: &text[start..i] })
    }

    /// Puts `span` back: its text comes next again, as tokens.
    pub fn unread(&mut self, span: &NumberSpan<'a>) {
        self.pos = span.offset;
    }

    /// The contents of the string whose opening quote is at byte `start`, unescaped; the
    /// position moves past its closing quote.
    fn escaped_string(&mut self, start: usize) -> Result<String, SceneError> {
        let text: &str = &self.file.text;
        let mut chars = text[start + 1..].char_indices();
        let mut s = String::new();
        let at = |i: usize| start + 1 + i;
        loop {
            match chars.next() {
                None | Some((_, '\n')) => {
                    let loc = self.file.location(start);
                    return Err(SceneError::syntax(&loc, &format!("\"{s}"), "unterminated string"));
                }
                Some((i, '"')) => {
                    self.pos = at(i) + 1;
                    return Ok(s);
                }
                Some((_, '\\')) => {
                    let e = match chars.next().map(|(_, c)| c) {
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
                            let loc = self.file.location(start);
                            return Err(SceneError::syntax(
                                &loc,
                                &format!("\\{shown}"),
                                "unknown escape sequence in string",
                            ));
                        }
                    };
                    s.push(e);
                }
                Some((_, c)) => s.push(c),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(text: &str) -> SourceFile {
        SourceFile::new(Arc::from(Path::new("t.pbrt")), None, text.to_string())
    }

    fn all(text: &str) -> Result<Vec<(TokenKind, String, u32, u32)>, SceneError> {
        let f = file(text);
        let mut t = Tokenizer::new(&f);
        let mut v = Vec::new();
        while let Some(tok) = t.next_token()? {
            let (line, col) = tok.loc().line_col();
            v.push((tok.kind, tok.text.into_owned(), line, col));
        }
        Ok(v)
    }

    /// Line and column of byte `offset`, counted from the start of `text`.
    fn counted(text: &str, offset: usize) -> (u32, u32) {
        let before = &text[..offset];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        (before.matches('\n').count() as u32 + 1, before[line_start..].chars().count() as u32 + 1)
    }

    #[test]
    fn locations_asked_in_any_order_are_counted_from_the_start() {
        let text = "a bb\n\n  λ \"é\" c\r\n[ 1\t2 ]   \u{2003}d\ne";
        let offsets: Vec<usize> = text.char_indices().map(|(i, _)| i).chain([text.len()]).collect();
        let f = file(text);
        // Forward, backward, and jumping by 7 around the text.
        let order = offsets
            .iter()
            .chain(offsets.iter().rev())
            .chain((0..offsets.len()).map(|i| &offsets[i * 7 % offsets.len()]));
        for &o in order {
            assert_eq!(f.location(o).line_col(), counted(text, o), "offset {o}");
        }
    }

    #[test]
    fn a_byte_order_mark_is_not_a_character() {
        assert_eq!(all("\u{feff}Shape \"x\"").unwrap()[1], (TokenKind::Str, "x".into(), 1, 7));
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
        assert_eq!(e.location().line(), 1);
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
