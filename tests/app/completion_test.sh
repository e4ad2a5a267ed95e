#!/usr/bin/env bash
# The bash completion (packaging/cdpowder.bash-completion) offers exactly the commands and the
# long options that `cdpowder COMMAND --help` lists.
#   completion_test.sh CDPOWDER COMPLETION_FILE
set -euo pipefail
cdpowder=$1
completion=$2
bash -n "$completion"  # it parses
status=0
help_commands=$("$cdpowder" --help | awk '/^Subcommands:/{on=1; next} on && NF {print $1}' | sort | tr '\n' ' ')
script_commands=$(grep -oP '^\s*local commands="\K[^"]+' "$completion" | tr ' ' '\n' | sort | tr '\n' ' ')
if [[ $help_commands != "$script_commands" ]]; then
  echo "completion_test: commands: --help lists '$help_commands', the completion '$script_commands'" >&2
  status=1
fi
for command in $help_commands; do
  from_help=$("$cdpowder" "$command" --help | grep -oE -- '--[a-z][a-z-]*' | sort -u | tr '\n' ' ')
  # the options of the command's case branch (several lines for sweep)
  from_script=$(awk -v c="$command" '
      $0 ~ "^[[:space:]]*(" c "|[a-z]+ \\| " c "|" c " \\| [a-z]+)\\)" {on=1}
      on {print}
      on && /;;/ {exit}' "$completion" | grep -oE -- '--[a-z][a-z-]*' | sort -u | tr '\n' ' ')
  if [[ $from_help != "$from_script" ]]; then
    echo "completion_test: $command: --help has '$from_help', the completion '$from_script'" >&2
    status=1
  fi
done
[[ $status -eq 0 ]] && echo "completion_test: the commands and options agree with --help"
exit $status
