//! The `delone` command-line mesher: `delone tri` speaks Triangle's switches,
//! `delone tet` TetGen's. Run `delone --help`.
#![forbid(unsafe_code)]

mod adapt;
mod args;
mod cutaway;
mod dual;
mod fail;
mod guard;
mod help;
mod jettison;
mod numbering;
mod paths;
mod plc;
mod progress;
mod pslg;
mod remesh;
mod run;
mod tetd;
mod tetjson;
mod tetout;
mod tetq;
mod tetq_bound;
mod tetq_left;
mod tetr;
mod threads;
mod tri_out;

use args::{Command, Mode, Usage};

fn fail(message: &str, code: i32) -> ! {
    eprintln!("delone: error: {message}");
    std::process::exit(code)
}

fn main() {
    let mut argv = std::env::args_os()
        .skip(1)
        .map(|a| a.to_string_lossy().into_owned());
    let sub = argv.next();
    let mode = match sub.as_deref() {
        Some("tri") => Mode::Tri,
        Some("tet") => Mode::Tet,
        Some("adapt") => match adapt::main(argv.collect()) {
            Ok(_) => return,
            Err(f) => fail(&f.message, f.code),
        },
        Some("--help") | Some("-h") | Some("help") => {
            print!("{}", help::MAIN);
            return;
        }
        Some("--version") => {
            println!("delone {}", env!("CARGO_PKG_VERSION"));
            return;
        }
        Some(other) => fail(
            &format!(
                "unknown subcommand {other:?} (expected tri, tet or adapt; see delone --help)"
            ),
            2,
        ),
        None => {
            eprint!("{}", help::MAIN);
            std::process::exit(2);
        }
    };
    let rest: Vec<String> = argv.collect();
    match args::parse(mode, rest) {
        Err(Usage(msg)) => fail(&msg, 2),
        Ok(Command::Help) => print!(
            "{}",
            match mode {
                Mode::Tri => help::TRI,
                Mode::Tet => help::TET,
            }
        ),
        Ok(Command::Version) => println!("delone {}", env!("CARGO_PKG_VERSION")),
        Ok(Command::Run(opts)) => {
            match progress::observe(!opts.out().quiet, || run::run(mode, &opts)) {
                Ok(0) => {}
                Ok(code) => std::process::exit(code),
                Err(f) => fail(&f.message, f.code),
            }
        }
    }
}
