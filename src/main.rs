use clap::Parser;

fn main() {
    // `@NAME` arguments become the connection options saved under NAME.
    let args = match axterm::cli::expanded_command_line() {
        Ok(args) => args,
        Err(message) => {
            eprintln!("axterm: {message}");
            std::process::exit(axterm::cli::EXIT_USAGE);
        }
    };
    let cli = axterm::cli::Cli::parse_from(args);
    std::process::exit(axterm::cli::run(cli));
}
