//! Subcommands of the `grove` tool by family, one folder each (its arguments and handlers), and
//! the helpers they share.

pub mod aerial;
pub mod bench;
pub mod models;
pub mod play;
pub mod render;
pub mod replay;
pub mod scene;
pub mod serve;
pub mod study;
pub mod test;

use std::path::Path;

use grove_systems::scene::Scene;

/// Formats an error and its causes as a single line.
pub fn one_line(e: &anyhow::Error) -> String {
    format!("{e:#}").replace('\n', " ")
}

/// A usage error of the argument parser as one line: clap's own first line (the error kind and
/// its message) and a pointer to `--help`, without the usage block and tips it prints below it.
pub fn usage_error_line(e: &clap::Error) -> String {
    // A negative number given to an option reads to the parser as an unknown flag; name the
    // option it was meant for.
    if e.kind() == clap::error::ErrorKind::UnknownArgument
        && let Some(clap::error::ContextValue::String(arg)) = e.get(clap::error::ContextKind::InvalidArg)
        && arg.parse::<f64>().is_ok()
    {
        let args: Vec<String> = std::env::args().collect();
        if let Some(i) = args.iter().position(|a| a == arg).filter(|&i| i > 0 && args[i - 1].starts_with("--")) {
            return format!(
                "error: invalid value '{arg}' for '{}': a negative number is not allowed there (see --help)",
                args[i - 1]
            );
        }
    }
    let text = e.render().to_string();
    let first = text.lines().map(str::trim).find(|l| !l.is_empty()).unwrap_or("error: bad arguments");
    let first = if first.starts_with("error:") { first.to_string() } else { format!("error: {first}") };
    format!("{first} (see --help)")
}

/// Replaces the default panic message (and backtrace) with one line. A panic is a bug in
/// grove; this keeps even that case to a single, clear line on stderr.
pub fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        let msg = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown cause".into());
        let at = info.location().map(|l| format!(" at {}:{}", l.file(), l.line())).unwrap_or_default();
        eprintln!("error: internal error{at}: {}; please report this", msg.replace('\n', " "));
    }));
}

/// Restores the default action of SIGPIPE (Rust ignores it), so that `grove … | head` ends
/// quietly when the reader closes the pipe, as other command-line tools do, instead of failing
/// to print and reporting that as an internal error.
pub fn quiet_on_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: called once at start-up, before any thread exists; SIG_DFL is a valid action.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// Loads a scene file, with the error naming the file.
pub fn load_scene(path: &Path) -> anyhow::Result<Scene> {
    Ok(Scene::load(path)?)
}

/// Prints a value as pretty JSON on stdout.
pub fn print_json<T: serde::Serialize>(value: &T) -> anyhow::Result<()> {
    println!("{}", serde_json::to_string_pretty(value)?);
    Ok(())
}
