//! The token stream a parser reads directives from: positional arguments, numbers and
//! parameter lists (`"type name" value` or `"type name" [ values ]`).
//!
//! As in pbrt-v4's parser, an included file's tokens take the place of the Include: the stream
//! reads a stack of files, and at the end of an included file goes on in the file that included
//! it, so a directive may begin in one file and end in another. Tokens borrow their text from
//! their file's, which is why every file read stays in the stream's [`SourceFiles`] until the
//! stream is dropped, and keep their own file's location.

use super::error::{Location, SceneError};
use super::number_list;
use super::params::{number_kind_of, parse_float, Param, ParamNames, ParamSet};
use super::tokenizer::{SourceFile, SourceFiles, Token, TokenKind, Tokenizer};
use std::path::PathBuf;
use std::sync::Arc;

/// Tokens of a file and the files it includes, with one token of look-ahead.
pub(super) struct Source<'a> {
    /// Where the texts of the files read are kept while tokens borrow them.
    store: &'a SourceFiles,
    /// The files being read, innermost last, each with its canonical path (for cycle checks).
    files: Vec<(Tokenizer<'a>, PathBuf)>,
    peeked: Option<Token<'a>>,
    /// The outermost file: "unexpected end of file" errors point at its end.
    outer: &'a SourceFile,
    /// The value tokens of the parameter being read (kept to reuse its allocation).
    values: Vec<Token<'a>>,
    /// The parameters of the list being read (kept to reuse its allocation).
    params: Vec<Param>,
    /// The parameter names read so far.
    names: ParamNames,
}

impl<'a> Source<'a> {
    /// Reads `file` (canonically `canonical`), keeping it and the files it includes in `store`.
    pub(super) fn new(store: &'a SourceFiles, file: SourceFile, canonical: PathBuf) -> Self {
        let outer = store.add(file);
        Self {
            store,
            files: vec![(Tokenizer::new(outer), canonical)],
            peeked: None,
            outer,
            values: Vec::new(),
            params: Vec::new(),
            names: ParamNames::default(),
        }
    }

    /// Reads `file` before the rest of the stream.
    pub(super) fn include(&mut self, file: SourceFile, canonical: PathBuf) {
        debug_assert!(self.peeked.is_none(), "a token read ahead would come before the included file");
        self.files.push((Tokenizer::new(self.store.add(file)), canonical));
    }

    /// The last line of the outermost file.
    fn end(&self) -> Location {
        Location::new(Arc::from(self.outer.path()), self.outer.text().lines().count().max(1) as u32, 1)
    }

    /// The canonical paths of the files being read, outermost first.
    pub(super) fn chain(&self) -> impl Iterator<Item = &PathBuf> {
        self.files.iter().map(|(_, c)| c)
    }

    pub(super) fn peek(&mut self) -> Result<Option<&Token<'a>>, SceneError> {
        while self.peeked.is_none() {
            let Some((tok, _)) = self.files.last_mut() else { break };
            self.peeked = tok.next_token()?;
            if self.peeked.is_none() {
                self.files.pop();
            }
        }
        Ok(self.peeked.as_ref())
    }

    pub(super) fn next(&mut self) -> Result<Option<Token<'a>>, SceneError> {
        self.peek()?;
        Ok(self.peeked.take())
    }

    /// The next token, which must exist; `what` names what the directive expects.
    pub(super) fn expect(&mut self, after: &Token, what: impl std::fmt::Display) -> Result<Token<'a>, SceneError> {
        match self.next()? {
            Some(t) => Ok(t),
            None => Err(SceneError::syntax(
                &self.end(),
                &after.text,
                format!("unexpected end of file: {} expects {what}", after.text),
            )),
        }
    }

    pub(super) fn string(&mut self, after: &Token, what: &str) -> Result<Token<'a>, SceneError> {
        let t = self.expect(after, what)?;
        if t.kind != TokenKind::Str {
            return Err(SceneError::syntax(&t.loc(), &t.display(), format!("{} expects {what}", after.text)));
        }
        Ok(t)
    }

    /// `N` numbers, bare or in one bracketed list.
    pub(super) fn numbers<const N: usize>(&mut self, after: &Token) -> Result<[f32; N], SceneError> {
        let bracketed = matches!(self.peek()?, Some(t) if t.kind == TokenKind::Open);
        let mut v = [0.0; N];
        // Plain numbers are read from the text (a scene of many instances has a `Transform [ … ]`
        // or a `Translate x y z` each); anything else goes through the tokens, which also say
        // what is wrong.
        if bracketed {
            self.next()?;
            if self.text_numbers(&mut v, true) {
                return Ok(v);
            }
        } else if let Some(first) = self.peeked.as_ref().filter(|t| t.kind == TokenKind::Word) {
            if let Ok(x) = number_list::read_float(&first.text) {
                v[0] = x;
                if self.text_numbers(&mut v[1..], false) {
                    self.peeked = None;
                    return Ok(v);
                }
            }
        }
        let n = N;
        for (found, x) in v.iter_mut().enumerate() {
            let t = self.expect(after, format_args!("{n} numbers"))?;
            if t.kind != TokenKind::Word {
                return Err(SceneError::syntax(
                    &t.loc(),
                    &t.display(),
                    format!("{} expects {n} numbers, found {found}", after.text),
                ));
            }
            *x = parse_float(&t)?;
        }
        if bracketed {
            let t = self.expect(after, "\"]\"")?;
            if t.kind != TokenKind::Close {
                return Err(SceneError::syntax(
                    &t.loc(),
                    &t.display(),
                    format!("{} expects exactly {n} numbers", after.text),
                ));
            }
        }
        Ok(v)
    }

    /// Reads `out` from the current file's text: the numbers up to the next `]` (`bracketed`,
    /// right after a `[`), or the next `out.len()` words; false, with nothing read, unless they
    /// are plain numbers and exactly as many as `out` holds.
    fn text_numbers(&mut self, out: &mut [f32], bracketed: bool) -> bool {
        let Some((tokens, _)) = self.files.last_mut() else { return false };
        let span = if bracketed { tokens.number_span() } else { tokens.word_span(out.len()) };
        let Some(span) = span else { return false };
        let read = number_list::read_exactly(span.text, out);
        if !read {
            tokens.unread(&span);
        }
        read
    }

    /// Right after the `[` of parameter `decl`: when `decl` holds numbers and the list is
    /// plain numbers up to its `]` in the same file, reads it from the text straight into `ps`
    /// and says so; else leaves it to the tokens.
    fn number_list(&mut self, decl: &Token, ps: &mut ParamSet) -> Result<bool, SceneError> {
        debug_assert!(self.peeked.is_none(), "the list's first token was read ahead");
        let Some(kind) = number_kind_of(decl) else { return Ok(false) };
        let Some(span) = self.files.last_mut().and_then(|(t, _)| t.number_span()) else { return Ok(false) };
        let numbers = number_list::read(&span, kind)?;
        ps.push(Param::from_numbers(decl, numbers, &mut self.names)?)?;
        Ok(true)
    }

    /// A parameter list: `"type name" value` or `"type name" [ values ]`, repeated.
    pub(super) fn params(&mut self, color_space: &'static str) -> Result<ParamSet, SceneError> {
        let mut ps = ParamSet::with_buffer(std::mem::take(&mut self.params), color_space);
        let mut values = std::mem::take(&mut self.values);
        while matches!(self.peek()?, Some(t) if t.kind == TokenKind::Str) {
            let decl = self.next()?.expect("peeked");
            values.clear();
            let first = self.expect(&decl, "a value")?;
            match first.kind {
                TokenKind::Open if self.number_list(&decl, &mut ps)? => continue,
                TokenKind::Open => loop {
                    let t = self.next()?.ok_or_else(|| {
                        SceneError::syntax(&first.loc(), "[", format!("unterminated [ for parameter \"{}\"", decl.text))
                    })?;
                    match t.kind {
                        TokenKind::Close => break,
                        TokenKind::Open => {
                            return Err(SceneError::syntax(&t.loc(), "[", "nested [ in a parameter list"))
                        }
                        _ => values.push(t),
                    }
                },
                TokenKind::Close => return Err(SceneError::syntax(&first.loc(), "]", "unexpected ]")),
                _ => values.push(first),
            }
            ps.push(Param::parse(&decl, &values, &mut self.names)?)?;
        }
        values.clear();
        self.values = values;
        let (ps, buffer) = ps.compact();
        self.params = buffer;
        Ok(ps)
    }
}
