//! Enums chosen by name on the command line and in scene files: one table of names per enum,
//! from which parsing, the canonical name and the list of valid names in messages all come.

/// A name that names none of an enum's values.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown {what} '{name}' (valid: {valid})")]
pub struct UnknownName {
    /// What the name should have named ("accelerator", "quadric mode", …).
    pub what: &'static str,
    /// The name as given.
    pub name: String,
    /// The valid names, comma-separated.
    pub valid: String,
}

/// The value `name` stands for in `table`.
pub fn parse<T: Copy + PartialEq>(
    table: &[(&'static str, T)],
    what: &'static str,
    name: &str,
) -> Result<T, UnknownName> {
    match table.iter().find(|(n, _)| *n == name) {
        Some(&(_, value)) => Ok(value),
        None => Err(UnknownName { what, name: name.into(), valid: valid(table) }),
    }
}

/// The canonical names of `table` (each value's first), comma-separated in table order.
pub fn valid<T: PartialEq>(table: &[(&'static str, T)]) -> String {
    let canonical = table.iter().enumerate().filter(|(i, (_, v))| !table[..*i].iter().any(|(_, w)| w == v));
    canonical.map(|(_, (n, _))| *n).collect::<Vec<_>>().join(", ")
}

/// Gives a fieldless enum its name table: `NAMES` (each name with its value; a value's first
/// name is canonical, later ones are aliases that parse but are not listed), `parse` (with an
/// [`UnknownName`] error naming `what`), `name` (the canonical name) and `valid_names`. The table
/// must name every value: `name` is a match over it.
macro_rules! name_table {
    ($ty:ident, $what:literal, { $($name:literal => $value:path),+ $(,)? }) => {
        impl $ty {
            /// Each name with its value; a value's first name is its canonical name.
            pub const NAMES: &'static [(&'static str, $ty)] = &[$(($name, $value)),+];

            /// The value a name from [`Self::NAMES`] stands for.
            pub fn parse(name: &str) -> Result<Self, $crate::named::UnknownName> {
                $crate::named::parse(Self::NAMES, $what, name)
            }

            /// The canonical name.
            #[allow(unreachable_patterns)]
            pub fn name(self) -> &'static str {
                match self {
                    $($value => $name,)+
                }
            }

            /// The canonical names, comma-separated, for messages.
            pub fn valid_names() -> String {
                $crate::named::valid(Self::NAMES)
            }
        }
    };
}
pub(crate) use name_table;

#[cfg(test)]
mod tests {
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    enum Kind {
        A,
        B,
    }
    name_table!(Kind, "kind", { "a" => Kind::A, "b" => Kind::B, "bee" => Kind::B });

    #[test]
    fn names_parse_and_print_canonically() {
        assert_eq!(Kind::parse("bee"), Ok(Kind::B));
        assert_eq!(Kind::B.name(), "b");
        assert_eq!(Kind::valid_names(), "a, b");
        let e = Kind::parse("c").unwrap_err();
        assert_eq!(e.to_string(), "unknown kind 'c' (valid: a, b)");
    }
}
