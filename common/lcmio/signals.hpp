#pragma once
// Shutdown on SIGINT / SIGTERM: the handler only sets a flag; the process's loop polls it and
// leaves cleanly (final PROCESS_STATUS, exit 0). One flag per process.
namespace lasonic::shutdown {

// Installs the handlers for SIGINT and SIGTERM (idempotent).
void installHandlers();
// True once SIGINT or SIGTERM arrived, or request() was called.
bool requested();
void request();

}  // namespace lasonic::shutdown
