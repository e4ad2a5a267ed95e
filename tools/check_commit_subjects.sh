#!/usr/bin/env bash
# Commit subjects are at most 72 characters, with the detail in the body (.gitmessage).
# Checked on the commits since the last release tag (v*), or since the commit that set the
# rule, at most the last 50; a clone without that history checks the last 50 it has.
set -euo pipefail
cd "$(dirname "$0")/.."
limit=72
rule_set_after=624e9e5b  # the last commit before the rule; older subjects are history
base=$(git describe --tags --abbrev=0 --match 'v*' 2>/dev/null || true)
if [ -z "$base" ] && git cat-file -e "${rule_set_after}^{commit}" 2>/dev/null; then
  base=$rule_set_after
fi
range=HEAD
[ -n "$base" ] && range="$base..HEAD"
bad=0
checked=0
while IFS=$'\t' read -r hash subject; do
  checked=$((checked + 1))
  length=$(printf '%s' "$subject" | wc -m)
  if [ "$length" -gt "$limit" ]; then
    echo "commit $hash: subject of $length characters (at most $limit): $subject"
    bad=$((bad + 1))
  fi
done < <(git log --no-merges -n 50 --format='%h%x09%s' "$range")
if [ "$bad" -gt 0 ]; then
  echo "check_commit_subjects: $bad of $checked subjects too long; put the detail in the body"
  exit 1
fi
echo "check_commit_subjects: $checked subjects of at most $limit characters"
