//! `--name VALUE` / `--name=VALUE` options and `--flag` switches, each at
//! most once, for the commands that take many of them (`bake`,
//! `verify-bake`).

/// The options found on a command line.
pub(crate) struct Parsed<'a> {
    values: Vec<(&'static str, &'a str)>,
    flags: Vec<&'static str>,
}

impl<'a> Parsed<'a> {
    /// Parses `given`; `valued` options take a value, `flags` do not. The
    /// error is a usage message naming the command.
    pub(crate) fn new(
        command: &str,
        given: &[&'a str],
        valued: &[&'static str],
        flags: &[&'static str],
    ) -> Result<Parsed<'a>, String> {
        let mut parsed = Parsed {
            values: Vec::new(),
            flags: Vec::new(),
        };
        let mut rest = given;
        while let Some((&option, after)) = rest.split_first() {
            rest = after;
            if let Some(&flag) = flags.iter().find(|&&f| f == option) {
                if parsed.flags.contains(&flag) {
                    return Err(format!("{command}: {flag} given twice"));
                }
                parsed.flags.push(flag);
                continue;
            }
            let (name, inline_value) = match option.split_once('=') {
                Some((name, value)) => (name, Some(value)),
                None => (option, None),
            };
            let Some(&name) = valued.iter().find(|&&k| k == name) else {
                return Err(format!("{command}: unknown option {option:?}"));
            };
            let value = if let Some(value) = inline_value {
                value
            } else {
                let Some((&value, after)) = rest.split_first() else {
                    return Err(format!("{command}: {name} needs a value"));
                };
                rest = after;
                value
            };
            if parsed.values.iter().any(|&(n, _)| n == name) {
                return Err(format!("{command}: {name} given twice"));
            }
            parsed.values.push((name, value));
        }
        Ok(parsed)
    }

    /// The value of `name`, if given.
    pub(crate) fn get(&self, name: &str) -> Option<&'a str> {
        self.values
            .iter()
            .find(|&&(n, _)| n == name)
            .map(|&(_, v)| v)
    }

    /// Whether the switch `name` was given.
    pub(crate) fn flag(&self, name: &str) -> bool {
        self.flags.contains(&name)
    }
}
