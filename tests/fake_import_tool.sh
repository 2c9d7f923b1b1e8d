#!/bin/sh
# fake_import_tool.sh - stands in for lucent-import in test_import_sandbox and misbehaves as
# $LUCENT_FAKE_IMPORT says (crash, hang, spin, garbage), to show the sandbox survives each one.
case "$LUCENT_FAKE_IMPORT" in
  crash) kill -SEGV $$ ;;
  hang) exec sleep 60 ;;
  spin) while :; do :; done ;;
  garbage) echo 'this is not JSON'; exit 0 ;;
  *) echo "fake_import_tool.sh: unknown LUCENT_FAKE_IMPORT '$LUCENT_FAKE_IMPORT'" >&2; exit 3 ;;
esac
