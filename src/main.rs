fn main() {
    // `@NAME` arguments become the connection options saved under NAME.
    let args = match axterm::cli::expanded_command_line() {
        Ok(args) => args,
        Err(message) => {
            eprintln!("axterm: {message}");
            std::process::exit(axterm::cli::EXIT_USAGE);
        }
    };
    // Several links (repeated --sim/--port/--tcp) are cut apart here.
    let cli = axterm::cli::links::parse_from(args).unwrap_or_else(|e| e.exit());
    std::process::exit(axterm::cli::run(cli));
}
