//! `meadow devices`: its arguments, and what it prints of the
//! library's work (src/commands/devices.rs).

use anyhow::Context as _;

use super::DeviceArgs;

#[derive(clap::Args)]
pub struct DevicesArgs {
    #[command(flatten)]
    device: DeviceArgs,
}

pub fn run(args: DevicesArgs) -> anyhow::Result<()> {
    let DevicesArgs { device } = args;
    let (devices, validation) =
        meadow::commands::devices::devices(&device.options()?).context("listing Vulkan devices")?;
    if devices.is_empty() {
        anyhow::bail!(meadow::Error::NoDevice);
    }
    for d in &devices {
        println!("{}", meadow::commands::devices::line(d));
    }
    if validation.enabled {
        println!(
            "validation: {} errors, {} warnings",
            validation.errors, validation.warnings
        );
        validation.check()?;
    }
    Ok(())
}
