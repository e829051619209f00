//! `meadow scenes`: the built-in scenes, or one of them as TOML.

#[derive(clap::Args)]
pub struct ScenesArgs {
    /// Write the built-in scene NAME as TOML to stdout instead of the list.
    #[arg(long, value_name = "NAME")]
    print: Option<String>,
}

pub fn run(args: ScenesArgs) -> anyhow::Result<()> {
    match args.print {
        Some(name) => print!("{}", meadow::commands::scenes::print(&name)?),
        None => print!("{}", meadow::commands::scenes::list()?),
    }
    Ok(())
}
