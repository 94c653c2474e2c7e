-- Headless Neovim as the client of `iface-lsp --stdio` (run by test_neovim.py).
-- Opens $IFACE_FILE, waits for diagnostics, asks for a hover and for completion,
-- and writes what arrived as JSON to $IFACE_OUT. Works on 0.7 (start_client +
-- buf_attach_client) and on 0.8+ (vim.lsp.start).
local out = {}
local function finish()
  vim.fn.writefile({ vim.fn.json_encode(out) }, vim.env.IFACE_OUT)
  vim.cmd("qall!")
end

local ok, err = pcall(function()
  vim.cmd("edit " .. vim.fn.fnameescape(vim.env.IFACE_FILE))
  local config = {
    name = "iface",
    cmd = { vim.env.IFACE_PYTHON, "-m", "iface", "--stdio" },
    root_dir = vim.fn.fnamemodify(vim.env.IFACE_FILE, ":h"),
  }
  local id
  if vim.lsp.start then
    id = vim.lsp.start(config)
    out.api = "vim.lsp.start"
  else
    id = vim.lsp.start_client(config)
    vim.lsp.buf_attach_client(0, id)
    out.api = "vim.lsp.start_client"
  end
  out.version = tostring(vim.version().major) .. "." .. tostring(vim.version().minor)

  vim.wait(30000, function() return #vim.diagnostic.get(0) > 0 end, 50)
  out.diagnostics = {}
  for _, d in ipairs(vim.diagnostic.get(0)) do
    table.insert(out.diagnostics, { lnum = d.lnum, col = d.col, message = d.message,
      code = d.code or (d.user_data and d.user_data.lsp and d.user_data.lsp.code) })
  end

  -- hover over the message name on line 3 ("message Reading {")
  vim.api.nvim_win_set_cursor(0, { 3, 9 })
  local hover = vim.lsp.buf_request_sync(0, "textDocument/hover", vim.lsp.util.make_position_params(), 20000)
  out.hover = ""
  for _, r in pairs(hover or {}) do
    if r.result and r.result.contents then out.hover = r.result.contents.value or "" end
  end

  -- complete at the start of the member line 4, where a type goes
  vim.api.nvim_win_set_cursor(0, { 4, 4 })
  local completion = vim.lsp.buf_request_sync(0, "textDocument/completion", vim.lsp.util.make_position_params(), 20000)
  out.completion = {}
  for _, r in pairs(completion or {}) do
    local items = r.result and (r.result.items or r.result) or {}
    for _, item in ipairs(items) do table.insert(out.completion, item.label) end
  end
end)
if not ok then out.error = tostring(err) end
finish()
