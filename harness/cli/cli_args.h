/* cli_args.h: the argument checks that report, predict, calibrate,
 * tune and advise share, with the same one-line messages. */
#ifndef ACCELBENCH_CLI_ARGS_H
#define ACCELBENCH_CLI_ARGS_H

/* Print that `arg` is an unknown or incomplete option of `accelbench cmd`;
 * returns 2 (bad input). */
int cli_bad_option(const char *cmd, const char *arg);

/* The one positional argument left after getopt (argv[optind]), or NULL
 * after printing why: none given (naming `what` and its placeholder
 * `name`), or more than one. */
const char *cli_one_operand(const char *cmd, const char *what, const char *name, int argc, char **argv);
/* cli_one_operand for a run folder (RUN_DIR). */
const char *cli_one_run_folder(const char *cmd, int argc, char **argv);

/* 0 when getopt left no argument (a command of options only), else 2
 * after printing the first one as unexpected. */
int cli_no_operands(const char *cmd, int argc, char **argv);

#endif
