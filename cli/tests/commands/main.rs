//! The `nearmiss` command as a user meets it: exit codes and messages on bad
//! scenes and query files, undecided runs, and `nearmiss test` for CI.

mod exit_codes;
mod query_file_errors;
mod readme_first_run;
mod scene_errors;
mod test_reports;
mod undecided_is_not_contact;
