//! Command-line flags for every registered method's settings, made at run time from the
//! registry (clap's builder API behind `#[command(flatten)]`): `--lattice 16` for `render` and
//! `view`, `--lattice 8,16,32` for the grids of `report` and `profile`. A setting several
//! methods share is one flag; its help names them.

use clap::builder::{PossibleValue, PossibleValuesParser};
use clap::{Arg, ArgAction, ArgMatches, Args, Command, FromArgMatches};

use crate::gi::registry;
use crate::gi::settings::{Kind, Setting};

/// `--method`'s values: `none` and every registered method, each with its description.
pub fn method_parser() -> PossibleValuesParser {
    let none = PossibleValue::new(registry::NONE).help("direct light only, no GI");
    PossibleValuesParser::new(
        std::iter::once(none)
            .chain(registry::methods().map(|m| PossibleValue::new(m.name).help(m.description))),
    )
}

/// The settings a user gave, as (name, value) in declaration order.
#[derive(Clone, Debug, Default)]
pub struct MethodSettings {
    pub values: Vec<(String, String)>,
}

/// The settings a user gave as lists, as (name, values) in declaration order.
#[derive(Clone, Debug, Default)]
pub struct MethodGrid {
    pub values: Vec<(String, Vec<String>)>,
}

impl MethodGrid {
    /// The single-value settings (the first value of each list).
    pub fn firsts(&self) -> Vec<(String, String)> {
        self.values
            .iter()
            .filter_map(|(name, values)| values.first().map(|v| (name.clone(), v.clone())))
            .collect()
    }
}

/// The flag of one setting; `list` makes it take comma-separated values.
fn setting_arg(setting: &'static Setting, methods: &[&str], list: bool) -> Arg {
    let default = match (setting.kind, setting.default) {
        (Kind::Flag, _) => String::new(),
        (_, d) => format!(" [default: {d}]"),
    };
    // Methods sharing a name may mean different things by it: each says its own then.
    let own: Vec<&Setting> = methods
        .iter()
        .filter_map(|m| registry::find(m))
        .filter_map(|m| m.settings.iter().find(|s| s.name == setting.name))
        .collect();
    let alike = own
        .iter()
        .all(|s| s.help == setting.help && s.default == setting.default);
    let help = if alike {
        format!("({}) {}{default}", methods.join(", "), setting.help)
    } else {
        methods
            .iter()
            .zip(&own)
            .map(|(m, s)| format!("({m}) {} [default: {}]", s.help, s.default))
            .collect::<Vec<_>>()
            .join("; ")
    };
    let arg = Arg::new(setting.name)
        .long(setting.name)
        .help(help)
        .help_heading("Method settings");
    match setting.kind {
        Kind::Flag => arg.action(ArgAction::SetTrue),
        _ => {
            let arg = arg
                .value_name("VALUE")
                .value_parser(clap::value_parser!(String))
                .allow_negative_numbers(true)
                .action(ArgAction::Set);
            if list {
                arg.value_delimiter(',').value_name("VALUES")
            } else {
                arg
            }
        }
    }
}

fn augment(cmd: Command, list: bool) -> Command {
    registry::all_settings()
        .into_iter()
        .fold(cmd, |cmd, (setting, methods)| {
            cmd.arg(setting_arg(setting, &methods, list))
        })
}

/// Every (setting, values given) in `matches`.
fn given(matches: &ArgMatches) -> Vec<(String, Vec<String>)> {
    let mut out = Vec::new();
    for (setting, _) in registry::all_settings() {
        let values: Vec<String> = match setting.kind {
            Kind::Flag => match matches.try_get_one::<bool>(setting.name) {
                Ok(Some(true)) => vec!["on".to_string()],
                _ => Vec::new(),
            },
            _ => match matches.try_get_many::<String>(setting.name) {
                Ok(Some(v)) => v.cloned().collect(),
                _ => Vec::new(),
            },
        };
        if !values.is_empty() {
            out.push((setting.name.to_string(), values));
        }
    }
    out
}

impl FromArgMatches for MethodSettings {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        let values = given(matches)
            .into_iter()
            .filter_map(|(name, values)| values.into_iter().last().map(|v| (name, v)))
            .collect();
        Ok(MethodSettings { values })
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl Args for MethodSettings {
    fn augment_args(cmd: Command) -> Command {
        augment(cmd, false)
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        augment(cmd, false)
    }
}

impl FromArgMatches for MethodGrid {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        Ok(MethodGrid {
            values: given(matches),
        })
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl Args for MethodGrid {
    fn augment_args(cmd: Command) -> Command {
        augment(cmd, true)
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        augment(cmd, true)
    }
}
